// What the light's frustum is fitted to: the light-space box of the receivers the camera sees (a min/max
// reduction of the G-buffer on the device), the map size the camera's pixels need and, once the map is drawn, the
// depth range of its casters and the penumbra widths its shadows have (kernels/fit.cl). host/views/views.h turns these
// into the light's view.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <vector>

#include "host/cl/buffer.h"
#include "host/cl/context.h"
#include "host/scene/light.h"
#include "host/scene/scene.h"
#include "kernels/shared/light_view.h"
#include "raster/rasterizer.h"

namespace penumbra {

// Light-eye box of the visible receivers. Spot lights: x, y are the tangents x/d, y/d (the unit a perspective
// map's texels are uniform in); directional lights: light-eye x, y. depth is linear light depth d = -z_eye.
struct ReceiverBounds {
  bool empty = true;  // the camera sees no surface (in front of the light)
  glm::vec2 lo{0.0f}, hi{0.0f};
  float depthMin = 0.0f, depthMax = 0.0f;
};

// The light's world -> eye matrix before fitting (its orientation does not depend on the fit). Throws
// std::invalid_argument for a point light, which has one per cube face (host/views/cube.h cubeFaceLight).
glm::mat4 lightEyeMatrix(const Light& light, const Bounds& scene);

// Box of the covered G-buffer pixels seen from `lightEye`. Launch "fit/fit_receivers_partial".
ReceiverBounds reduceReceivers(Context& ctx, const GBuffer& gbuffer, const glm::mat4& lightEye, bool perspective);

// Auto map sizes are whole numbers of the rasterizer's 128-texel bins (RASTER_BIN_PIXEL_LOG2).
inline constexpr int kMapSizeStep = 128;
// The histograms the frame's choices are quantiles of (the map size's need, the penumbra widths and occluder
// distances) are measured on at least this many pixels and not many more: a larger frame is sampled on a grid of
// stride floor(sqrt(pixels / kFitSamples)) (fitSampleStride: 1 up to 181x181, 3 at 480x270, 5 at 640x360, 15 at
// 1920x1080), each sample against its own neighbours and texels. The map size's 0.9-quantile's rank moves by about
// sqrt(0.9 * 0.1 / 8192), 0.33 % of the pixels (a 0.05-quantile's by 0.24 %), far inside a histogram bin (9 % of the
// size). Bounds (receivers, depth ranges) are never sampled.
inline constexpr size_t kFitSamples = 8192;
uint32_t fitSampleStride(size_t pixels);

// The map size the camera's pixels need (`--map-size auto`): per covered pixel, the size at which its shorter screen
// step to an on-plane neighbour spans one texel of the first of `views` whose map holds it (Luksch sec. 7, eq. 5, the
// measure of pssm's resolutionError; a directional or spot light's one view, or a point light's six cube faces, each
// fitted at any size); `size` is the `quantile` of those over the pixels, rounded up to a multiple of kMapSizeStep
// within [minSize, maxSize]. Launch "fit/fit_size_partial" (a histogram of 8 bins an octave, so `needed` is within 9 %
// above the exact quantile).
struct MapSizeNeed {
  int size = 0;         // the chosen size; minSize when no pixel was counted
  double needed = 0.0;  // the quantile before rounding and clamping (0: no pixel counted)
  uint64_t pixels = 0;  // pixels counted
};
MapSizeNeed neededMapSize(Context& ctx, const GBuffer& gbuffer, std::span<const LightViewGpu> views, double quantile,
                          int minSize, int maxSize);

// `needed` texels rounded up to a multiple of kMapSizeStep within [minSize, maxSize].
int roundedMapSize(double needed, int minSize, int maxSize);

// The penumbra half-width a `quantile` of the camera's shadowed pixels reach, in texels at the receiver: what a
// fixed-kernel filter's auto width matches (host/techniques/moment_map.h). Per covered pixel facing the light, in the
// hard shadow of the nearest texel of `map` (sm's receiver with `bias`), lv_penumbra_texels of its receiver and that
// occluder (Fernando 2005: the light's size times the occluder-receiver distance over the occluder's, a sun's times
// the distance); a histogram of 8 bins an octave over [2^-8, 2^8) texels, so `halfWidth` is within 5 % of the exact
// quantile inside that range. Launch "fit/fit_penumbra_partial".
struct ReceiverBias {
  float constant, slope, normalOffset;  // sc_receiver's ShadowBias, in texel footprints
};
struct PenumbraWidth {
  double halfWidth = 0.0;  // texels; 0 when no pixel was counted or the quantile lies at an occluder's contact
  uint64_t pixels = 0;     // shadowed pixels counted
};
PenumbraWidth measurePenumbraWidth(Context& ctx, const GBuffer& gbuffer, const Buffer<float>& map,
                                   const Buffer<LightViewGpu>& view, const ReceiverBias& bias, double quantile);

// The same pixels' occluder distance (the receiver's light depth minus the occluder's) that `quantile` of them reach,
// in world units: savsm's --savsm-occluder-distance auto. Binned as the widths over [2^-8, 2^8) `unit`s (within 5 %
// inside that range; the host passes the scene's size / 16). Throws std::invalid_argument for a quantile outside
// (0, 1] or a unit <= 0.
struct OccluderDistance {
  double distance = 0.0;  // world units; 0 when no pixel was counted or at an occluder's contact
  uint64_t pixels = 0;
};
OccluderDistance measureOccluderDistance(Context& ctx, const GBuffer& gbuffer, const Buffer<float>& map,
                                         const Buffer<LightViewGpu>& view, const ReceiverBias& bias, double quantile,
                                         float unit);

// Finite min and max of `count` depths (+INFINITY background ignored); {+inf, -inf} when none is finite.
// Launch "fit/fit_depth_partial".
struct DepthRange {
  float min, max;
};
DepthRange reduceDepthRange(Context& ctx, const Buffer<float>& depth, size_t count);

// What a drawn map tells about the size a frame needs beyond its pixels' (`--map-size auto`, host/pipeline/map_size.h),
// summed over the maps added (a point light's cube faces):
// - the penumbra half-widths of the camera's shadowed pixels, in texels of the map (measurePenumbraWidth's histogram);
// - the widths of the casters' features along the map's rows and columns, in texels (kernels/fit.cl
//   fit_detail_partial: runs of texels entered by a step towards the light and left by a step away from it, each a
//   depth jump of more than 8 texel widths: a leg, a pole, a bar between alpha holes), 1..63 texels and 64 or wider.
// Launches "fit/fit_penumbra_partial" (with `penumbrae`) and "fit/fit_detail_partial".
class MapDetailMeter {
 public:
  void add(Context& ctx, const GBuffer& gbuffer, const Buffer<float>& depth, int size, const Buffer<LightViewGpu>& view,
           const ReceiverBias& bias, bool penumbrae);
  // The half-width `quantile` of the shadowed pixels reach (within 5 %, as measurePenumbraWidth's).
  PenumbraWidth penumbra(double quantile) const;
  // Features counted, and the width (whole texels) that `quantile` of them do not exceed; 0 with none counted.
  uint64_t features() const;
  double featureWidth(double quantile) const;

 private:
  std::vector<uint64_t> penumbra_, features_;
};

// The tight view-depth range [near, far] of what the camera sees (a min/max reduction of the G-buffer's linear depth,
// as sample-distribution shadow maps do), widened a little so the extreme pixels are inside; [1, 2] for a frame that
// sees nothing. What pssm's splits, the LiSPSM warp and jittered's reduction are planned over.
struct ViewDepthRange {
  float near = 1.0f, far = 2.0f;
};
ViewDepthRange tightViewDepth(Context& ctx, const GBuffer& gbuffer);

}  // namespace penumbra
