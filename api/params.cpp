// The technique registry (host/techniques/registry.h) and pn_params: a technique and its parameter values, validated
// as the CLI validates its options.
#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <mutex>
#include <string>

#include "api/guard.h"
#include "api/handles.h"

using penumbra::api::guard;
using penumbra::api::require;

namespace {

// The registry keeps every string alive for the program's life; choices are joined once per parameter here.
const std::string& joinedChoices(const penumbra::ParamSpec& spec) {
  static std::mutex mutex;
  static std::map<const penumbra::ParamSpec*, std::string> joined;
  std::lock_guard lock(mutex);
  auto [it, added] = joined.try_emplace(&spec);
  if (added)
    for (const std::string& choice : spec.choices) it->second += (it->second.empty() ? "" : ",") + choice;
  return it->second;
}

}  // namespace

extern "C" {

size_t pn_technique_count(void) { return penumbra::techniques().size(); }

const char* pn_technique_name(size_t index) {
  const auto& all = penumbra::techniques();
  return index < all.size() ? all[index].name.c_str() : nullptr;
}

const char* pn_technique_description(size_t index) {
  const auto& all = penumbra::techniques();
  return index < all.size() ? all[index].description.c_str() : nullptr;
}

size_t pn_technique_param_count(const char* technique) {
  size_t count = 0;
  guard([&] {
    count = penumbra::findTechnique(require(technique, "pn_technique_param_count", "technique")).params.size();
  });
  return count;
}

pn_status pn_technique_param(const char* technique, size_t index, pn_param_info* info) {
  return guard([&] {
    const penumbra::TechniqueInfo& t = penumbra::findTechnique(require(technique, "pn_technique_param", "technique"));
    require(info, "pn_technique_param", "info");
    if (index >= t.params.size())
      throw std::out_of_range(fmt::format("pn_technique_param: technique '{}' has {} parameters, not {}", t.name,
                                          t.params.size(), index + 1));
    const penumbra::ParamSpec& spec = t.params[index];
    *info = pn_param_info{spec.name.c_str(), spec.help.c_str(),           spec.defaultValue, spec.min,
                          spec.max,          joinedChoices(spec).c_str(), spec.text ? 1 : 0, spec.textDefault.c_str()};
  });
}

pn_status pn_params_create(const char* technique, pn_params** params) {
  return guard([&] {
    require(params, "pn_params_create", "params");
    auto created = std::make_unique<pn_params>();
    created->technique = &penumbra::findTechnique(require(technique, "pn_params_create", "technique"));
    created->params = penumbra::Params(created->technique->params);
    created->description = created->params.describe();
    *params = created.release();
  });
}

pn_status pn_params_retain(pn_params* params) { return penumbra::api::retainHandle(params, "pn_params_retain"); }

pn_status pn_params_release(pn_params* params) { return penumbra::api::releaseHandle(params); }

pn_status pn_params_set(pn_params* params, const char* name, const char* value) {
  return guard([&] {
    pn_params& p = *require(params, "pn_params_set", "params");
    const std::string key = require(name, "pn_params_set", "name");
    if (!p.technique->hasParam(key))
      throw std::invalid_argument(fmt::format("\"{}\" is not a parameter of technique '{}'", key, p.technique->name));
    const std::string text = require(value, "pn_params_set", "value");
    p.params.set(key, text);
    p.given[key] = text;
    p.description = p.params.describe();
  });
}

pn_status pn_params_get(const pn_params* params, const char* name, double* value) {
  return guard([&] {
    const pn_params& p = *require(params, "pn_params_get", "params");
    const std::string key = require(name, "pn_params_get", "name");
    if (!p.technique->hasParam(key))
      throw std::invalid_argument(fmt::format("\"{}\" is not a parameter of technique '{}'", key, p.technique->name));
    const auto& specs = p.technique->params;
    if (std::any_of(specs.begin(), specs.end(),
                    [&](const penumbra::ParamSpec& spec) { return spec.name == key && spec.text; }))
      throw std::invalid_argument(fmt::format("\"{}\" is a text parameter (pn_params_describe shows its value)", key));
    *require(value, "pn_params_get", "value") = p.params.get(key);
  });
}

const char* pn_params_technique(const pn_params* params) {
  return params != nullptr ? params->technique->name.c_str() : nullptr;
}

const char* pn_params_describe(const pn_params* params) {
  return params != nullptr ? params->description.c_str() : nullptr;
}

}  // extern "C"
