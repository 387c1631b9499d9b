// Parameter sweeps of `penumbra bench`: "--sweep map-size=512,1024,2048" parsed, and each technique's settings as
// the cartesian product of the sweeps over parameters it has (the others are skipped and reported). A sweep may
// move several parameters together: "--sweep pssm-splits+map-size=1+2048,4+1024" gives two settings (splits 1 at
// 2048², splits 4 at 1024²: the same total texels), for the techniques that have all of them.
#pragma once

#include <map>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "host/techniques/technique.h"

namespace penumbra {

struct Sweep {
  std::string param;                // parameter name(s) without dashes, as given ("map-size", "a+b")
  std::vector<std::string> names;   // the parameters it moves
  std::vector<std::string> values;  // as given, in order; one '+'-joined part per name
};

// "NAME=a,b,c" or "NAME1+NAME2=a1+a2,b1+b2" (a leading "--" on a name is allowed). Throws std::invalid_argument
// naming the text when a name or a value is empty, there is no '=', or a value has the wrong number of parts.
Sweep parseSweep(std::string_view text);

// A sweep value "default" holds its parameter at the technique's own default (auto for --map-size where the
// technique has it, its fixed size otherwise), over any value given as an option: the default beside fixed values in
// one interleaved run.
inline constexpr const char* kSweepDefault = "default";

struct Setting {
  std::map<std::string, std::string> values;  // swept parameter -> value for this setting
  std::set<std::string> defaults;             // swept parameters held at the technique's default (kSweepDefault)
  std::string label;                          // "map-size=512 blur-radius=1" in sweep order; "default" when none
};

// The settings of one technique: one per combination of the values of the sweeps over parameters it has (the first
// sweep varies slowest); a single "default" setting when none applies. `skipped` gets the sweeps it lacks.
std::vector<Setting> expandSweeps(const TechniqueInfo& technique, const std::vector<Sweep>& sweeps,
                                  std::vector<std::string>* skipped = nullptr);

// Throws std::invalid_argument when a parameter is swept twice or none of `list` has it.
void checkSweeps(const std::vector<Sweep>& sweeps, const std::vector<const TechniqueInfo*>& list);

}  // namespace penumbra
