// Sweep parsing and expansion into per-technique settings.
#include "tools/eval/sweep.h"

#include <fmt/format.h>

#include <algorithm>
#include <set>
#include <stdexcept>

namespace penumbra {
namespace {

bool hasAll(const TechniqueInfo& info, const Sweep& sweep) {
  return std::all_of(sweep.names.begin(), sweep.names.end(), [&](const std::string& n) { return info.hasParam(n); });
}

std::vector<std::string> split(std::string_view text, char separator) {
  std::vector<std::string> parts;
  while (true) {
    const size_t at = text.find(separator);
    parts.emplace_back(text.substr(0, at));
    if (at == std::string_view::npos) return parts;
    text.remove_prefix(at + 1);
  }
}

}  // namespace

Sweep parseSweep(std::string_view text) {
  const auto bad = [&](const char* why) {
    return std::invalid_argument(fmt::format("--sweep '{}': {} (expected NAME=a,b,c or NAME1+NAME2=a1+a2,b1+b2)", text, why));
  };
  const size_t eq = text.find('=');
  if (eq == std::string_view::npos) throw bad("no '='");
  Sweep sweep;
  for (std::string name : split(text.substr(0, eq), '+')) {
    if (name.starts_with("--")) name.erase(0, 2);
    if (name.empty()) throw bad("empty parameter name");
    sweep.param += (sweep.param.empty() ? "" : "+") + name;
    sweep.names.push_back(std::move(name));
  }
  for (const std::string& value : split(text.substr(eq + 1), ',')) {
    const std::vector<std::string> parts = split(value, '+');
    if (std::any_of(parts.begin(), parts.end(), [](const std::string& p) { return p.empty(); })) throw bad("empty value");
    if (parts.size() != sweep.names.size()) throw bad("a value needs one '+'-joined part per parameter");
    sweep.values.push_back(value);
  }
  return sweep;
}

std::vector<Setting> expandSweeps(const TechniqueInfo& technique, const std::vector<Sweep>& sweeps,
                                  std::vector<std::string>* skipped) {
  std::vector<Setting> settings{Setting{}};
  for (const Sweep& sweep : sweeps) {
    if (!hasAll(technique, sweep)) {
      if (skipped != nullptr) skipped->push_back(sweep.param);
      continue;
    }
    std::vector<Setting> next;
    for (const Setting& base : settings)
      for (const std::string& value : sweep.values) {
        Setting s = base;
        const std::vector<std::string> parts = split(value, '+');
        for (size_t k = 0; k < parts.size(); ++k) {
          if (parts[k] == kSweepDefault)
            s.defaults.insert(sweep.names[k]);
          else
            s.values[sweep.names[k]] = parts[k];
        }
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
    for (const std::string& name : sweep.names)
      if (!seen.insert(name).second) throw std::invalid_argument(fmt::format("--sweep {} given twice", name));
    if (std::none_of(list.begin(), list.end(), [&](const TechniqueInfo* t) { return hasAll(*t, sweep); }))
      throw std::invalid_argument(fmt::format("--sweep {}: no technique in the list has that parameter (all of them)", sweep.param));
  }
}

}  // namespace penumbra
