// The list of techniques `penumbra render --technique` knows.
#include "host/techniques/registry.h"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

namespace penumbra {

const std::vector<TechniqueInfo>& techniques() {
  static const std::vector<TechniqueInfo> kTechniques = {
      smTechnique(),    pcfTechnique(),  pcssTechnique(),  vsmTechnique(),      evsm2Technique(),
      evsm4Technique(), esmTechnique(),  msmTechnique(),   savsmTechnique(),    vssmTechnique(),
      lvsmTechnique(),  pssmTechnique(), psvsmTechnique(), jitteredTechnique(), fvsmTechnique(), izbTechnique(),
  };
  return kTechniques;
}

bool TechniqueInfo::hasParam(const std::string& param) const {
  return std::any_of(params.begin(), params.end(), [&](const ParamSpec& spec) { return spec.name == param; });
}

const TechniqueInfo& findTechnique(const std::string& name) {
  std::string known;
  for (const TechniqueInfo& info : techniques()) {
    if (info.name == name) return info;
    known += (known.empty() ? "" : ", ") + info.name;
  }
  throw std::invalid_argument(fmt::format("unknown technique '{}' (known: {})", name, known));
}

Params techniqueParams(const TechniqueInfo& info, const ParamValues& values, bool strict) {
  Params params(info.params);
  for (const auto& [name, value] : values) {
    if (!info.hasParam(name)) {
      if (strict) throw std::invalid_argument(fmt::format("--{} does not apply to technique '{}'", name, info.name));
      continue;
    }
    params.set(name, value);
  }
  return params;
}

void refuseUnsupportedLight(const Light& light, const TechniqueInfo& technique) {
  if (light.type != LightType::Point || technique.shadowsPointLights()) return;
  std::string others;
  for (const TechniqueInfo& info : techniques())
    if (info.shadowsPointLights()) others += (others.empty() ? "" : ", ") + info.name;
  throw std::invalid_argument(fmt::format("light {} is a point light, which technique {} cannot shadow ({}); {}",
                                          light.label(), technique.name, technique.pointLightRefusal,
                                          others.empty() ? "no technique can" : "point lights work with " + others));
}

}  // namespace penumbra
