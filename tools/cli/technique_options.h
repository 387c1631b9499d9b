// Every technique's parameters as --NAME options (`render`, `bench`), and how the values given turn into one
// technique's Params: strictly (render: a parameter the technique lacks is an error) or leniently (bench: it applies
// to the techniques that have it).
#pragma once

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <CLI/CLI.hpp>
#include <map>
#include <set>
#include <stdexcept>
#include <string>

#include "host/techniques/technique.h"

namespace penumbra::cli {

using penumbra::ParamValues;  // name (no dashes) -> text as given

// Declares each parameter once, even when several techniques share it.
inline void addTechniqueOptions(CLI::App* sub, ParamValues& values) {
  std::set<std::string> declared;
  for (const TechniqueInfo& info : techniques())
    for (const ParamSpec& spec : info.params) {
      if (!declared.insert(spec.name).second) continue;
      std::string help = spec.help + (spec.text              ? fmt::format(" [default '{}']", spec.textDefault)
                                      : spec.choices.empty() ? fmt::format(" [default {}]", spec.defaultValue)
                                                             : fmt::format(" ({})", fmt::join(spec.choices, "|")));
      sub->add_option_function<std::string>(
             "--" + spec.name, [&values, name = spec.name](const std::string& v) { values[name] = v; }, help)
          ->group("Technique parameters");
    }
}

// The core's (host/techniques/technique.h), under the names the commands use.
using penumbra::techniqueParams;

}  // namespace penumbra::cli
