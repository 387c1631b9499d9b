// Parameter sweeps of `penumbra bench`: "--sweep map-size=512,1024,2048" parsed, and each technique's settings as
// the cartesian product of the sweeps over parameters it has (the others are skipped and reported).
#pragma once

#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "host/techniques/technique.h"

namespace penumbra {

struct Sweep {
  std::string param;                // parameter name without dashes
  std::vector<std::string> values;  // as given, in order
};

// "NAME=a,b,c" (a leading "--" on NAME is allowed). Throws std::invalid_argument naming the text when the name or a
// value is empty or there is no '='.
Sweep parseSweep(std::string_view text);

struct Setting {
  std::map<std::string, std::string> values;  // swept parameter -> value for this setting
  std::string label;                          // "map-size=512 blur-radius=1" in sweep order; "default" when none
};

// The settings of one technique: one per combination of the values of the sweeps over parameters it has (the first
// sweep varies slowest); a single "default" setting when none applies. `skipped` gets the sweeps it lacks.
std::vector<Setting> expandSweeps(const TechniqueInfo& technique, const std::vector<Sweep>& sweeps,
                                  std::vector<std::string>* skipped = nullptr);

// Throws std::invalid_argument when a parameter is swept twice or none of `list` has it.
void checkSweeps(const std::vector<Sweep>& sweeps, const std::vector<const TechniqueInfo*>& list);

}  // namespace penumbra
