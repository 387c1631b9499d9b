// Every technique's parameters as --NAME options (`render`, `bench`), collected as ParamValues; the core's
// techniqueParams (host/techniques/technique.h) turns them into one technique's Params, strictly (render) or
// leniently (bench).
#pragma once

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <CLI/CLI.hpp>
#include <set>
#include <string>

#include "host/techniques/technique.h"

namespace penumbra::cli {

// Declares each parameter once, even when several techniques share it.
inline void addTechniqueOptions(CLI::App* sub, ParamValues& values) {
  std::set<std::string> declared;
  for (const TechniqueInfo& info : techniques())
    for (const ParamSpec& spec : info.params) {
      if (!declared.insert(spec.name).second) continue;
      std::string help = spec.help + (spec.text ? fmt::format(" [default '{}']", spec.textDefault)
                                      : spec.isAuto(spec.defaultValue) ? fmt::format(" [default {}]", spec.autoName)
                                      : spec.choices.empty()           ? fmt::format(" [default {}]", spec.defaultValue)
                                                             : fmt::format(" ({})", fmt::join(spec.choices, "|")));
      sub->add_option_function<std::string>(
             "--" + spec.name, [&values, name = spec.name](const std::string& v) { values[name] = v; }, help)
          ->group("Technique parameters");
    }
}

}  // namespace penumbra::cli
