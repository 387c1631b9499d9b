// Sweep parsing and expansion into per-technique settings.
#include "host/eval/sweep.h"

#include <fmt/format.h>

#include <algorithm>
#include <set>
#include <stdexcept>

namespace penumbra {
namespace {

bool hasParam(const TechniqueInfo& info, const std::string& name) {
  return std::any_of(info.params.begin(), info.params.end(), [&](const ParamSpec& s) { return s.name == name; });
}

}  // namespace

Sweep parseSweep(std::string_view text) {
  const auto bad = [&](const char* why) {
    return std::invalid_argument(fmt::format("--sweep '{}': {} (expected NAME=a,b,c)", text, why));
  };
  const size_t eq = text.find('=');
  if (eq == std::string_view::npos) throw bad("no '='");
  std::string_view name = text.substr(0, eq);
  if (name.starts_with("--")) name.remove_prefix(2);
  if (name.empty()) throw bad("empty parameter name");
  Sweep sweep{std::string(name), {}};
  std::string_view rest = text.substr(eq + 1);
  while (true) {
    const size_t comma = rest.find(',');
    const std::string_view value = rest.substr(0, comma);
    if (value.empty()) throw bad("empty value");
    sweep.values.emplace_back(value);
    if (comma == std::string_view::npos) break;
    rest.remove_prefix(comma + 1);
  }
  return sweep;
}

std::vector<Setting> expandSweeps(const TechniqueInfo& technique, const std::vector<Sweep>& sweeps,
                                  std::vector<std::string>* skipped) {
  std::vector<Setting> settings{Setting{}};
  for (const Sweep& sweep : sweeps) {
    if (!hasParam(technique, sweep.param)) {
      if (skipped != nullptr) skipped->push_back(sweep.param);
      continue;
    }
    std::vector<Setting> next;
    for (const Setting& base : settings)
      for (const std::string& value : sweep.values) {
        Setting s = base;
        s.values[sweep.param] = value;
        s.label += (s.label.empty() ? "" : " ") + sweep.param + "=" + value;
        next.push_back(std::move(s));
      }
    settings = std::move(next);
  }
  for (Setting& s : settings)
    if (s.label.empty()) s.label = "default";
  return settings;
}

void checkSweeps(const std::vector<Sweep>& sweeps, const std::vector<const TechniqueInfo*>& list) {
  std::set<std::string> seen;
  for (const Sweep& sweep : sweeps) {
    if (!seen.insert(sweep.param).second)
      throw std::invalid_argument(fmt::format("--sweep {} given twice", sweep.param));
    if (std::none_of(list.begin(), list.end(), [&](const TechniqueInfo* t) { return hasParam(*t, sweep.param); }))
      throw std::invalid_argument(fmt::format("--sweep {}: no technique in the list has that parameter", sweep.param));
  }
}

}  // namespace penumbra
