// `esm`: exponential shadow maps (Annen et al. 2008) on the shared moment pipeline, one channel (MomentKind::Esm):
// e^(c (d - 1)) filtered linearly up to c = 80, the depth filtered in log space beyond (kernels/esm.cl), so the
// exponent is not held to fp32's range and can follow the scene: under auto, large enough that the occluders nearest
// their receivers still darken them (host/views/light_fit.h measureOccluderDistance).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "host/techniques/moment_map.h"
#include "host/techniques/registry.h"
#include "host/views/light_fit.h"

namespace penumbra {
namespace {

constexpr double kAutoExponent = -1.0;  // esm-exponent auto (outside [0, max])
// The visibility auto's exponent leaves a receiver at the quantile's occluder distance: e^(-c distance) = 0.02, what
// the umbra metric counts as umbra in the reference (docs/evaluation.md). Measured on poles
// (docs/techniques/moments.md): 0.1 there left 7 % of the umbra above 0.1.
constexpr double kUmbraLight = 0.02;

// esm-exponent, or under auto ln(1 / 0.02) over the esm-exponent-quantile of the camera's hard-shadowed pixels'
// occluder distances in normalised depth, within esm-exponent-min..max; recorded in the header.
double frameExponent(ShadowFrame& frame, const ShadowMap& map, const MomentSettings& s) {
  if (!s.esmAuto) return s.esmExponent;
  const float range = map.view.gpu.zFar - map.view.gpu.zNear;
  // The histogram's unit: 1/16 of the map's depth range, so its octaves suit any scene scale.
  const OccluderDistance d = measureOccluderDistance(frame.ctx, frame.gbuffer, map.targets.depth, map.gpu,
                                                     s.map.receiverBias(), s.esmQuantile, std::max(range, 1e-6f) / 16.0f);
  const double lo = s.esmMin, hi = std::max(lo, s.esmMax);
  const double normalised = d.distance / range;
  double exponent = lo;  // no shadowed pixel: nothing to darken
  if (d.pixels > 0)      // occluders at distance 0 (contact) need the sharpest step
    exponent = normalised > 0.0 ? std::clamp(std::log(1.0 / kUmbraLight) / normalised, lo, hi) : hi;
  // 6 significant digits, as auto has always rounded it: frames stay identical to earlier versions'.
  exponent = std::stod(fmt::format("{:.6g}", exponent));
  frame.attributes["penumbra:esm-exponent"] =
      d.pixels == 0 ? fmt::format("auto {:.4g} (no shadowed pixel measured)", exponent)
                    : fmt::format("auto {:.4g} (quantile {} of {} shadowed pixels: occluder {:.4g} of the depth range)",
                                  exponent, s.esmQuantile, d.pixels, normalised);
  return exponent;
}

MomentTechniqueSpec esmSpec() {
  MomentTechniqueSpec spec{MomentKind::Esm, "kernels/esm.cl", "esm_visibility", false, 1};
  spec.configure = [](ShadowFrame& frame, const ShadowMap& map, const MomentSettings& s, MomentsConfig& config,
                      MomentShade& shade) {
    config.esmExponent = esmClampExponent(static_cast<float>(frameExponent(frame, map, s)), config.storage);
    shade.expPositive = config.esmExponent;
    shade.esmLogSpace = esmLogSpace(config.esmExponent) ? 1u : 0u;
  };
  return spec;
}

}  // namespace

TechniqueInfo esmTechnique() {
  ParamSpec exponent{"esm-exponent", kAutoExponent, 0, esmMaxExponent(MomentStorage::Float32),
                     fmt::format("ESM exponent c of e^(c d), d the normalised depth in [0, 1] (log space above {:g}; "
                                 "at most {:g} with half moment storage); auto: ln 50 over the occluder distance (in "
                                 "normalised depth) --esm-exponent-quantile of the shadowed pixels reach",
                                 MOMENTS_ESM_LINEAR_EXPONENT, esmMaxExponent(MomentStorage::Float16))};
  exponent.autoName = "auto";
  exponent.autoValue = kAutoExponent;
  std::vector<ParamSpec> extra = {
      exponent,
      {"esm-exponent-quantile", 0.02, 0.001, 1,
       "--esm-exponent auto: the share of the camera's shadowed pixels whose occluder is nearer than the distance "
       "the exponent darkens to 0.02"},
      {"esm-exponent-min", 80, 0, esmMaxExponent(MomentStorage::Float32),
       "--esm-exponent auto: the smallest exponent (the paper's 80)"},
      {"esm-exponent-max", esmMaxExponent(MomentStorage::Float32), 0, esmMaxExponent(MomentStorage::Float32),
       "--esm-exponent auto: the largest exponent"}};
  std::vector<ParamSpec> params = momentMapParams(extra);
  positiveWarpBlurMax(params);
  return {"esm", "Exponential shadow maps: filtered e^(c d) against e^(c t), in log space beyond c = 80", params,
          momentTechniqueFactory(esmSpec())};
}

}  // namespace penumbra
