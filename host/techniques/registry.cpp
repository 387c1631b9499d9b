// The list of techniques `penumbra render --technique` knows.
#include "host/techniques/registry.h"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

namespace penumbra {

const std::vector<TechniqueInfo>& techniques() {
  static const std::vector<TechniqueInfo> kTechniques = {
      smTechnique(),
      pcfTechnique(),
      pcssTechnique(),
      vsmTechnique(),
      evsm2Technique(),
      evsm4Technique(),
      esmTechnique(),
      msmTechnique(),
      savsmTechnique(),
      vssmTechnique(),
      lvsmTechnique(),
      pssmTechnique(),
      psvsmTechnique(),
      jitteredTechnique(),
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

}  // namespace penumbra
