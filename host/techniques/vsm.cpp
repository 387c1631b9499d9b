// `vsm`: variance shadow maps (Donnelly & Lauritzen 2006) on the shared moment pipeline
// (host/techniques/moment_map.h): Cantelli bound, minimum variance, bleeding reduction (kernels/vsm.cl).
#include "host/techniques/moment_map.h"
#include "host/techniques/registry.h"

namespace penumbra {

namespace {

MomentTechniqueSpec vsmSpec() {
  MomentTechniqueSpec spec{MomentKind::Vsm, "kernels/vsm.cl", "vsm_visibility"};
  spec.configure = [](ShadowFrame&, const ShadowMap&, const MomentSettings& s, MomentsConfig&, MomentShade& shade) {
    s.chebyshev.apply(shade);
  };
  return spec;
}

}  // namespace

TechniqueInfo vsmTechnique() {
  std::vector<ParamSpec> params = momentMapParams(chebyshevParams());
  blurredPenumbraMapSize(params);
  return {"vsm", "Variance shadow maps: filtered depth moments and the one-tailed Chebyshev bound", params,
          momentTechniqueFactory(vsmSpec())};
}

}  // namespace penumbra
