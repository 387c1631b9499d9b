// --map-size auto: the light's view probed at a fixed size, the pixels' needs reduced on the device
// (host/views/light_fit.h neededMapSize), the size the technique's instance is made with.
#include "host/pipeline/map_size.h"

#include <fmt/format.h>

#include <algorithm>
#include <span>
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

// The share of the probe's caster features whose width map-size-detail is about: the thinnest.
constexpr double kDetailQuantile = 0.05;

// The views the technique will fit, at `size`: a point light's six cube faces (their guard band as --cube-guard
// gives it at kProbeSize), or the light's one view (fitWarpedLightView, the LiSPSM warp included).
std::vector<LightView> probeViews(ShadowFrame& frame, const Params& params, int size) {
  std::vector<LightView> views;
  if (frame.light.type == LightType::Point) {
    const float guard = std::clamp(static_cast<float>(params.get("cube-guard")), 0.0f,
                                   CUBE_MAX_GUARD_FRACTION * static_cast<float>(kProbeSize));
    const float tangent = cube_window_tangent(guard, kProbeSize);
    for (int face = 0; face < CUBE_FACES; ++face)
      views.push_back(fitLightView(cubeFaceLight(frame.light, face, tangent), frame.scene.bounds(), size));
  } else {
    const WarpedFit fit{WarpSettings::from(params), params.getInt("fit") == 1};
    views.push_back(fitWarpedLightView(frame, fit, size, 0.0f));
  }
  return views;
}

// The probe's needs: each light view drawn at kMapProbeSize and measured (host/views/light_fit.h MapDetailMeter).
struct DrawnNeeds {
  double penumbra = 0.0, detail = 0.0;  // map sizes; 0: not measured or nothing to measure
  double cap = 0.0;                     // the size beyond which the pixels' need buys nothing; 0: none
  double reach = 0.0;                   // the size beyond which the technique's kernels clamp the median; 0: none
  std::string note;
};
DrawnNeeds drawnNeeds(ShadowFrame& frame, const Params& params, MapProbe& probe, int minSize, int maxSize,
                      const std::function<double(int)>& kernelReach) {
  DrawnNeeds needs;
  const double penumbraTexels = params.get("map-size-penumbra"), detailTexels = params.get("map-size-detail");
  const double capTexels = params.get("map-size-penumbra-max");
  const bool penumbrae = (penumbraTexels > 0.0 || capTexels > 0.0 || kernelReach) && frame.light.isArea();
  if (!penumbrae && !(detailTexels > 0.0)) return needs;
  const ReceiverBias bias{static_cast<float>(params.get("bias")), static_cast<float>(params.get("slope-bias")),
                          static_cast<float>(params.get("normal-offset"))};
  MapDetailMeter meter;
  for (LightView& view : probeViews(frame, params, kMapProbeSize)) {
    view.raster.writeTriangleIds = false;  // depths are what it measures
    view.raster.casterLight = rasterLightOf(frame.light);  // it measures casters and shadowed pixels: no ground
    frame.raster.draw(view.raster, probe.targets);
    if (probe.view.empty()) probe.view.allocate(frame.ctx, 1, CL_MEM_READ_ONLY);
    probe.view.upload(frame.ctx, std::span<const LightViewGpu>(&view.gpu, 1));
    meter.add(frame.ctx, frame.gbuffer, probe.targets.depth, kMapProbeSize, probe.view, bias, penumbrae);
  }
  constexpr double probeSize = kMapProbeSize;
  if (penumbrae && penumbraTexels > 0.0) {
    const double quantile = params.get("map-size-penumbra-quantile");
    const PenumbraWidth width = meter.penumbra(quantile);
    if (width.pixels > 0) {
      // A quantile at a contact (0 wide) asks for the most texels there are.
      needs.penumbra = width.halfWidth > 0.0 ? probeSize * penumbraTexels / width.halfWidth : maxSize;
      needs.note += fmt::format("; penumbrae: quantile {} of {} shadowed pixels {:.3g} texels wide at {} need {:.0f}",
                                quantile, width.pixels, width.halfWidth, kMapProbeSize, needs.penumbra);
    }
  }
  // The median half-width, which wide penumbrae are judged by (the pixels' cap, the kernels' reach).
  const PenumbraWidth median = penumbrae ? meter.penumbra(0.5) : PenumbraWidth{};
  if (penumbrae && capTexels > 0.0) {
    if (median.pixels > 0 && median.halfWidth > 0.0) {
      needs.cap = probeSize * capTexels / median.halfWidth;
      needs.note += fmt::format("; median penumbra {:.3g} texels wide at {} caps the pixels' need at {:.0f}",
                                median.halfWidth, kMapProbeSize, needs.cap);
    }
  }
  if (penumbrae && kernelReach) {
    // The largest size (a multiple of 128, as roundedMapSize gives) whose kernels hold the median half-width.
    const auto holds = [&](int size) { return median.halfWidth * size / probeSize <= kernelReach(size); };
    if (median.pixels > 0 && median.halfWidth > 0.0 && !holds(maxSize)) {
      int size = roundedMapSize(maxSize, minSize, maxSize);
      while (size > minSize && !holds(size)) size = std::max(minSize, size - 128);
      needs.reach = size;
      needs.note +=
          fmt::format("; its kernels' {:.0f}-texel reach holds that median up to {}", kernelReach(size), size);
    }
  }
  if (detailTexels > 0.0 && meter.features() > 0) {
    const double width = meter.featureWidth(kDetailQuantile);
    needs.detail = probeSize * detailTexels / width;
    needs.note += fmt::format("; casters: {:.0f} % of {} features {} texels wide at {} need {:.0f}",
                              kDetailQuantile * 100.0, meter.features(), width, kMapProbeSize, needs.detail);
  }
  return needs;
}

}  // namespace

bool autoMapSize(const Params& params) { return params.isAuto("map-size"); }

int sizeMapForFrame(ShadowFrame& frame, const Params& params, MapProbe& probe,
                    const std::function<double(int)>& kernelReach) {
  std::vector<LightViewGpu> views;
  for (const LightView& view : probeViews(frame, params, kProbeSize)) views.push_back(view.gpu);
  const double quantile = params.get("map-size-quantile");
  const int minSize = params.getInt("map-size-min"), maxSize = params.getInt("map-size-max");
  const MapSizeNeed need = neededMapSize(frame.ctx, frame.gbuffer, views, quantile, minSize, maxSize);
  const DrawnNeeds drawn = drawnNeeds(frame, params, probe, minSize, maxSize, kernelReach);
  // Wide penumbrae cap what the pixels ask for; the narrow end of the penumbrae and thin casters are not capped, but
  // everything is where the technique's kernels would clamp the median penumbra (on default.json under a radius-2 spot,
  // vssm's 128 texels: 3840^2 had MAE 0.0191, 2048^2 0.0109; pcss's 64 at 1536^2 0.0139, at 1024^2 0.0079).
  const double pixels = drawn.cap > 0.0 ? std::min(need.needed, drawn.cap) : need.needed;
  double wanted = std::max({pixels, drawn.penumbra, drawn.detail});
  if (drawn.reach > 0.0) wanted = std::min(wanted, drawn.reach);
  const int size = roundedMapSize(wanted, minSize, maxSize);
  frame.pixelsMapSize = need.pixels == 0 ? 0 : roundedMapSize(need.needed, minSize, maxSize);
  frame.attributes["penumbra:map-size"] = need.pixels == 0
                                              ? fmt::format("auto {} (no pixel measured{})", size, drawn.note)
                                              : fmt::format("auto {} (pixels: quantile {} of {} pixels need {:.0f}{})",
                                                            size, quantile, need.pixels, need.needed, drawn.note);
  return size;
}

void checkMapSizeRange(const Params& params) {
  if (!params.has("map-size-min") || !params.has("map-size-max")) return;
  const int lo = params.getInt("map-size-min"), hi = params.getInt("map-size-max");
  if (lo > hi)
    throw std::invalid_argument(
        fmt::format("--map-size-min {} is above --map-size-max {} (auto map sizes lie between)", lo, hi));
}

}  // namespace penumbra
