// --map-size auto: the light's view probed at a fixed size, the pixels' needs reduced on the device
// (host/views/light_fit.h neededMapSize), the size the technique's instance is made with.
#include "host/pipeline/map_size.h"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include "host/techniques/warp.h"
#include "host/views/cube.h"
#include "host/views/light_fit.h"
#include "host/views/views.h"

namespace penumbra {
namespace {

// The size the views are fitted at: any would do (the need scales with it), this one keeps the texel steps of
// typical pixels near 1, far from float round-off either way.
constexpr int kProbeSize = 1024;

}  // namespace

bool autoMapSize(const Params& params) { return params.isAuto("map-size"); }

int sizeMapForFrame(ShadowFrame& frame, const Params& params) {
  std::vector<LightViewGpu> views;
  if (frame.light.type == LightType::Point) {
    const float guard = std::clamp(static_cast<float>(params.get("cube-guard")), 0.0f,
                                   CUBE_MAX_GUARD_FRACTION * static_cast<float>(kProbeSize));
    const float tangent = cube_window_tangent(guard, kProbeSize);
    for (int face = 0; face < CUBE_FACES; ++face)
      views.push_back(fitLightView(cubeFaceLight(frame.light, face, tangent), frame.scene.bounds(), kProbeSize).gpu);
  } else {
    const WarpedFit fit{WarpSettings::from(params), params.getInt("fit") == 1};
    views.push_back(fitWarpedLightView(frame, fit, kProbeSize, 0.0f).gpu);
  }
  const double quantile = params.get("map-size-quantile");
  const MapSizeNeed need = neededMapSize(frame.ctx, frame.gbuffer, views, quantile, params.getInt("map-size-min"),
                                         params.getInt("map-size-max"));
  frame.attributes["penumbra:map-size"] = need.pixels == 0
                                              ? fmt::format("auto {} (no pixel measured)", need.size)
                                              : fmt::format("auto {} (quantile {} of {} pixels needs {:.0f})",
                                                            need.size, quantile, need.pixels, need.needed);
  return need.size;
}

void checkMapSizeRange(const Params& params) {
  if (!params.has("map-size-min") || !params.has("map-size-max")) return;
  const int lo = params.getInt("map-size-min"), hi = params.getInt("map-size-max");
  if (lo > hi)
    throw std::invalid_argument(fmt::format("--map-size-min {} is above --map-size-max {} (auto map sizes lie between)",
                                            lo, hi));
}

}  // namespace penumbra
