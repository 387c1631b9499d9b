// `vsm`: variance shadow maps (Donnelly & Lauritzen 2006) on the shared moment pipeline
// (host/techniques/moment_map.h): Cantelli bound, minimum variance, bleeding reduction (kernels/vsm.cl).
#include "host/techniques/moment_map.h"
#include "host/techniques/registry.h"

namespace penumbra {

TechniqueInfo vsmTechnique() {
  return {"vsm", "Variance shadow maps: filtered depth moments and the one-tailed Chebyshev bound",
          momentMapParams(chebyshevParams()), [](const Params& p) {
            MomentTechniqueSpec spec{MomentKind::Vsm, "kernels/vsm.cl", "vsm_visibility"};
            spec.configure = [](const Params& q, MomentsConfig&, MomentShade& s) { setChebyshevShade(q, s); };
            return std::make_unique<MomentTechnique>(spec, p);
          }};
}

}  // namespace penumbra
