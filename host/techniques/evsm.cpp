// `evsm2` and `evsm4`: exponential variance shadow maps (Lauritzen & McCool 2008, sec. 7) on the shared
// moment pipeline: the positive warp alone, or both warps and the smaller bound (kernels/evsm.cl). The
// exponents are bounded by the moment storage (fp32: 42, fp16: 5.54) of e^(2c) and its box sums (evsmMaxExponent).
#include "host/techniques/moment_map.h"
#include "host/techniques/registry.h"

namespace penumbra {
namespace {

std::vector<ParamSpec> evsmParams(bool negative) {
  const double max = evsmMaxExponent(MomentStorage::Float32);
  std::vector<ParamSpec> params = chebyshevParams();
  params.push_back({"evsm-positive", 40, 0, max, "EVSM exponent c+ of the warp e^(c+ x), x = 2d - 1 in [-1, 1]"});
  if (negative) params.push_back({"evsm-negative", 5, 0, max, "EVSM exponent c- of the warp -e^(-c- x)"});
  return params;
}

MomentTechniqueSpec evsmSpec(bool four) {
  MomentTechniqueSpec spec{four ? MomentKind::Evsm4 : MomentKind::Evsm2, "kernels/evsm.cl", "evsm_visibility"};
  spec.configure = [four](ShadowFrame&, const ShadowMap&, const MomentSettings& s, MomentsConfig& config,
                          MomentShade& shade) {
    s.chebyshev.apply(shade);
    config.evsmPositive = evsmClampExponent(s.evsmPositive, config.storage);
    config.evsmNegative = four ? evsmClampExponent(s.evsmNegative, config.storage) : 0.0f;
    shade.expPositive = config.evsmPositive;
    shade.expNegative = config.evsmNegative;
  };
  return spec;
}

TechniqueInfo evsmTechnique(bool four) {
  std::vector<ParamSpec> params = momentMapParams(evsmParams(four));
  four ? blurredPenumbraMapSize(params) : positiveWarpBlurMax(params);
  return {four ? "evsm4" : "evsm2",
          four ? "Exponential VSM with positive and negative warps (minimum of the two bounds)"
               : "Exponential VSM with the positive warp",
          params, momentTechniqueFactory(evsmSpec(four))};
}

}  // namespace

TechniqueInfo evsm2Technique() { return evsmTechnique(false); }
TechniqueInfo evsm4Technique() { return evsmTechnique(true); }

}  // namespace penumbra
