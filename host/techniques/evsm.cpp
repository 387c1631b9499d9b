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

TechniqueInfo evsmTechnique(bool four) {
  const MomentKind kind = four ? MomentKind::Evsm4 : MomentKind::Evsm2;
  std::vector<ParamSpec> params = momentMapParams(evsmParams(four));
  if (!four) positiveWarpBlurMax(params);
  return {four ? "evsm4" : "evsm2",
          four ? "Exponential VSM with positive and negative warps (minimum of the two bounds)"
               : "Exponential VSM with the positive warp",
          params, [kind, four](const Params& p) {
            MomentTechniqueSpec spec{kind, "kernels/evsm.cl", "evsm_visibility"};
            spec.configure = [four](const Params& q, MomentsConfig& config, MomentShade& s) {
              setChebyshevShade(q, s);
              config.evsmPositive = evsmClampExponent(static_cast<float>(q.get("evsm-positive")), config.storage);
              config.evsmNegative =
                  four ? evsmClampExponent(static_cast<float>(q.get("evsm-negative")), config.storage) : 0.0f;
              s.expPositive = config.evsmPositive;
              s.expNegative = config.evsmNegative;
            };
            return std::make_unique<MomentTechnique>(spec, p);
          }};
}

}  // namespace

TechniqueInfo evsm2Technique() { return evsmTechnique(false); }
TechniqueInfo evsm4Technique() { return evsmTechnique(true); }

}  // namespace penumbra
