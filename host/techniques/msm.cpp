// `msm`: moment shadow maps, Hamburger 4MSM (Peters & Klein 2015, Algorithm 2) on the shared moment
// pipeline, with the moment bias alpha and bleeding reduction (kernels/msm.cl).
#include <algorithm>

#include "host/techniques/moment_map.h"
#include "host/techniques/registry.h"

namespace penumbra {
namespace {

// Smallest moment bias with fp16 storage. The bias must outweigh the rounding of the stored moments (Peters &
// Klein 2015, sec. 4, size it for their 16-bit unorm moments); half keeps 11 significant bits, steps up to 4.9e-4
// below 1, and a planar occluder over a parallel receiver (tests/techniques_moments_test.cpp) needs 1e-3: 6e-4
// worst error against box-filtered PCF, 1.8e-2 with the fp32 default 3e-5.
constexpr float kHalfMinMomentBias = 1e-3f;

MomentTechniqueSpec msmSpec() {
  MomentTechniqueSpec spec{MomentKind::Msm, "kernels/msm.cl", "msm_visibility"};
  spec.configure = [](ShadowFrame&, const ShadowMap&, const MomentSettings& s, MomentsConfig& config,
                      MomentShade& shade) {
    shade.momentBias = s.msmBias;
    if (config.storage == MomentStorage::Float16) shade.momentBias = std::max(shade.momentBias, kHalfMinMomentBias);
    shade.bleeding = s.chebyshev.bleeding;
  };
  return spec;
}

}  // namespace

TechniqueInfo msmTechnique() {
  std::vector<ParamSpec> extra = {
      {"msm-bias", 3e-5, 0, 0.1,
       "MSM moment bias alpha: moments move towards (1/2, 1/2, 1/2, 1/2) by this share (at least 1e-3 with fp16 "
       "moment storage)"},
      bleedingParam()};
  std::vector<ParamSpec> params = momentMapParams(extra);
  blurredPenumbraMapSize(params);
  return {"msm", "Moment shadow maps: four moments and the Hamburger lower bound", params,
          momentTechniqueFactory(msmSpec())};
}

}  // namespace penumbra
