// `msm`: moment shadow maps, Hamburger 4MSM (Peters & Klein 2015, Algorithm 2) on the shared moment
// pipeline, with the moment bias alpha and bleeding reduction (kernels/msm.cl).
#include "host/techniques/moment_map.h"
#include "host/techniques/registry.h"

namespace penumbra {

TechniqueInfo msmTechnique() {
  std::vector<ParamSpec> extra = {
      {"msm-bias", 3e-5, 0, 0.1, "MSM moment bias alpha: moments move towards (1/2, 1/2, 1/2, 1/2) by this share"},
      bleedingParam()};
  return {"msm", "Moment shadow maps: four moments and the Hamburger lower bound", filteredMomentParams(extra),
          [](const Params& p) {
            MomentTechniqueSpec spec{MomentKind::Msm, "kernels/msm.cl", "msm_visibility"};
            spec.configure = [](const Params& q, MomentsConfig&, MomentShade& s) {
              s.momentBias = static_cast<float>(q.get("msm-bias"));
              s.bleeding = static_cast<float>(q.get("bleeding-reduction"));
            };
            return std::make_unique<MomentTechnique>(spec, p);
          }};
}

}  // namespace penumbra
