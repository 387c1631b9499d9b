// `esm`: exponential shadow maps (Annen et al. 2008) on the shared moment pipeline; the filtered e^(c x) is
// the first channel of the moments stage's EVSM2 encoding, so no stage of its own (kernels/esm.cl).
#include "host/techniques/moment_map.h"
#include "host/techniques/registry.h"

namespace penumbra {

TechniqueInfo esmTechnique() {
  const double max = evsmMaxExponent(MomentStorage::Float32);
  std::vector<ParamSpec> extra = {
      {"esm-exponent", 40, 0, max, "ESM exponent c of e^(c x), x = 2d - 1 in [-1, 1] (the paper's 2c on [0, 1])"}};
  std::vector<ParamSpec> params = momentMapParams(extra);
  positiveWarpBlurMax(params);
  return {"esm", "Exponential shadow maps: filtered e^(c d) against e^(c t)", params, [](const Params& p) {
            MomentTechniqueSpec spec{MomentKind::Evsm2, "kernels/esm.cl", "esm_visibility", false, 1};
            spec.configure = [](const Params& q, MomentsConfig& config, MomentShade& s) {
              config.evsmPositive = evsmClampExponent(static_cast<float>(q.get("esm-exponent")), config.storage);
              s.expPositive = config.evsmPositive;
            };
            return std::make_unique<MomentTechnique>(spec, p);
          }};
}

}  // namespace penumbra
