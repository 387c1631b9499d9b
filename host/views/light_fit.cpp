// Device reductions for the light fit: a few work-groups, each reducing its share to a partial the host finishes.
#include "host/views/light_fit.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <stdexcept>
#include <vector>

#include "host/cl/kernel.h"
#include "host/scene/camera.h"
#include "raster/constants.h"

namespace penumbra {
namespace {

constexpr size_t kFitGroup = 256;           // FIT_GROUP in kernels/fit.cl
constexpr size_t kMaxGroups = 1024;         // partials the host finishes
constexpr size_t kCpuGroupsPerUnit = 4;     // at most these per compute unit on a CPU (chunkFor)
constexpr size_t kSizeBins = 128;           // FIT_SIZE_BINS
constexpr double kSizeBinsPerOctave = 8.0;  // FIT_SIZE_BINS_PER_OCTAVE, also the penumbra histogram's
constexpr size_t kPenumbraBins = 128;       // FIT_PENUMBRA_BINS
constexpr double kPenumbraLog2Min = -8.0;   // FIT_PENUMBRA_LOG2_MIN
constexpr size_t kDetailBins = 64;          // FIT_DETAIL_BINS

// Chunk per group so that few enough groups cover `count` items, each chunk a multiple of the group: at most
// kMaxGroups on a GPU, which wants many; kCpuGroupsPerUnit per compute unit on a CPU, which runs a group's barriers as
// loops over its work-items, so that each group streams a long chunk (PoCL, default.json at 640x360: vsm's map
// reduction 3.2 -> 0.34 ms, pssm's four 15.8 -> 0.8 ms).
uint32_t chunkFor(const Context& ctx, size_t count) {
  const size_t maxGroups =
      ctx.info().cpuLayouts() ? kCpuGroupsPerUnit * std::max<size_t>(1, ctx.info().computeUnits) : kMaxGroups;
  const size_t perGroup = (count + maxGroups - 1) / maxGroups;
  return static_cast<uint32_t>(std::max(kFitGroup, roundUp(perGroup, kFitGroup)));
}

// The sample grid a quantile histogram of `g` is measured on (fitSampleStride, fit_sample_pixel) and its launch.
struct SampleLaunch {
  uint32_t stride;
  size_t count;   // samples
  size_t groups;  // as many as chunkFor's chunks; each takes every groups-th block of the samples (FIT_FOR_SAMPLES)
};

SampleLaunch sampleLaunch(const Context& ctx, const GBuffer& g) {
  SampleLaunch s;
  s.stride = fitSampleStride(static_cast<size_t>(g.width) * static_cast<size_t>(g.height));
  s.count = static_cast<size_t>((g.width + s.stride - 1) / s.stride) *
            static_cast<size_t>((g.height + s.stride - 1) / s.stride);
  const uint32_t chunk = chunkFor(ctx, s.count);
  s.groups = (s.count + chunk - 1) / chunk;
  return s;
}

cl_float4 row(const glm::mat4& m, int r) { return {{m[0][r], m[1][r], m[2][r], m[3][r]}}; }

// A histogram of `bins` bins summed over the work-groups' partials, and its count.
struct Histogram {
  std::vector<uint64_t> bins;
  uint64_t total = 0;
};
Histogram sumPartials(const std::vector<uint32_t>& parts, size_t bins) {
  Histogram h{std::vector<uint64_t>(bins, 0)};
  for (size_t i = 0; i < parts.size(); ++i) h.bins[i % bins] += parts[i];
  for (uint64_t b : h.bins) h.total += b;
  return h;
}

// The first bin at which the running count reaches `quantile` of the total (the last bin at most).
size_t quantileBin(const Histogram& h, double quantile) {
  const double target = quantile * static_cast<double>(h.total);
  uint64_t running = 0;
  size_t bin = 0;
  while (bin + 1 < h.bins.size() && static_cast<double>(running += h.bins[bin]) < target) ++bin;
  return bin;
}

}  // namespace

glm::mat4 lightEyeMatrix(const Light& light, const Bounds& sceneBounds) {
  if (light.type == LightType::Point)  // never a point taken for a directional: its faces are spots (cube.h)
    throw std::invalid_argument("lightEyeMatrix: a point light has no single frustum (it is drawn as cube faces)");
  const Bounds scene = sceneBounds.orUnit();
  const glm::vec3 axis = light.axis();
  if (light.type == LightType::Spot) return glm::lookAt(light.position, light.target, chooseUp(axis));
  const float radius = std::max(scene.radius(), 1e-6f);
  const glm::vec3 center = scene.center();
  return glm::lookAt(center - axis * (2.0f * radius), center, chooseUp(axis));
}

uint32_t fitSampleStride(size_t pixels) {
  return static_cast<uint32_t>(std::max(1.0, std::floor(std::sqrt(static_cast<double>(pixels) / kFitSamples))));
}

ReceiverBounds reduceReceivers(Context& ctx, const GBuffer& gbuffer, const glm::mat4& lightEye, bool perspective) {
  ReceiverBounds bounds;
  const size_t count = static_cast<size_t>(gbuffer.width) * static_cast<size_t>(gbuffer.height);
  if (count == 0) return bounds;
  const uint32_t chunk = chunkFor(ctx, count);
  const size_t groups = (count + chunk - 1) / chunk;
  Buffer<cl_float4> partial(ctx, 2 * groups);
  Kernel kernel(ctx, "kernels/fit.cl", "fit_receivers_partial", "fit");
  kernel
      .args(gbuffer.position, static_cast<uint32_t>(count), row(lightEye, 0), row(lightEye, 1), row(lightEye, 2),
            static_cast<int>(perspective), partial)
      .moves(count * sizeof(cl_float4))  // floor: read every position once
      .launch(groups * kFitGroup, kFitGroup);
  const std::vector<cl_float4> parts = partial.download(ctx);
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  for (size_t g = 0; g < groups; ++g) {
    lo = glm::min(lo, glm::vec3(parts[2 * g].s[0], parts[2 * g].s[1], parts[2 * g].s[2]));
    hi = glm::max(hi, glm::vec3(parts[2 * g + 1].s[0], parts[2 * g + 1].s[1], parts[2 * g + 1].s[2]));
  }
  if (!(lo.z <= hi.z)) return bounds;  // nothing covered (or nothing in front of a spot light)
  bounds.empty = false;
  bounds.lo = glm::vec2(lo);
  bounds.hi = glm::vec2(hi);
  bounds.depthMin = lo.z;
  bounds.depthMax = hi.z;
  return bounds;
}

MapSizeNeed neededMapSize(Context& ctx, const GBuffer& gbuffer, std::span<const LightViewGpu> views, double quantile,
                          int minSize, int maxSize) {
  if (views.empty()) throw std::invalid_argument("neededMapSize: no views");
  if (!(quantile > 0.0 && quantile <= 1.0) || minSize < 1 || maxSize < minSize)
    throw std::invalid_argument("neededMapSize: quantile outside (0, 1] or an empty size range");
  MapSizeNeed need;
  need.size = minSize;
  if (gbuffer.width == 0 || gbuffer.height == 0) return need;
  const SampleLaunch s = sampleLaunch(ctx, gbuffer);
  Buffer<uint32_t> partial(ctx, s.groups * kSizeBins);
  const Buffer<LightViewGpu> viewBuffer(ctx, views, CL_MEM_READ_ONLY);
  Kernel kernel(ctx, "kernels/fit.cl", "fit_size_partial", "fit");
  kernel
      .args(gbuffer.position, gbuffer.normal, static_cast<uint32_t>(gbuffer.width),
            static_cast<uint32_t>(gbuffer.height), s.stride, viewBuffer, static_cast<uint32_t>(views.size()),
            partial)
      .moves(s.count * 4 * sizeof(cl_float4))  // floor: each sample's position and normal, two neighbours' positions
      .launch(s.groups * kFitGroup, kFitGroup);
  const Histogram bins = sumPartials(partial.download(ctx), kSizeBins);
  need.pixels = bins.total;
  if (need.pixels == 0) return need;
  // The bin at which the running count reaches the quantile; its upper edge is the size.
  need.needed = std::exp2(static_cast<double>(quantileBin(bins, quantile) + 1) / kSizeBinsPerOctave);
  need.size = roundedMapSize(need.needed, minSize, maxSize);
  return need;
}

int roundedMapSize(double needed, int minSize, int maxSize) {
  // Up to a whole number of the rasterizer's bins, not to a power of two: a need of 2233 draws 2304^2 texels, not
  // 4096^2 (3.2 times as many).
  static_assert(kMapSizeStep == 1 << RASTER_BIN_PIXEL_LOG2, "auto sizes are whole rasterizer bins");
  const double steps = std::ceil(std::min(needed, static_cast<double>(maxSize)) / kMapSizeStep);
  return std::clamp(static_cast<int>(steps) * kMapSizeStep, minSize, maxSize);
}

namespace {

enum PenumbraMeasure { kHalfWidth = 0, kDistance = 1 };  // FIT_PENUMBRA_HALF_WIDTH, FIT_PENUMBRA_DISTANCE

// fit_penumbra_partial's histogram of `measure` (distances over `unit`).
Histogram penumbraBins(Context& ctx, const GBuffer& gbuffer, const Buffer<float>& map, const Buffer<LightViewGpu>& view,
                       const ReceiverBias& bias, PenumbraMeasure measure, float unit) {
  if (gbuffer.width == 0 || gbuffer.height == 0) return {std::vector<uint64_t>(kPenumbraBins, 0)};
  const SampleLaunch s = sampleLaunch(ctx, gbuffer);
  Buffer<uint32_t> partial(ctx, s.groups * kPenumbraBins);
  Kernel kernel(ctx, "kernels/fit.cl", "fit_penumbra_partial", "fit");
  kernel
      .args(gbuffer.position, gbuffer.normal, static_cast<uint32_t>(gbuffer.width),
            static_cast<uint32_t>(gbuffer.height), s.stride, map, view, bias.constant, bias.slope, bias.normalOffset,
            static_cast<int>(measure), unit, partial)
      .moves(s.count * (2 * sizeof(cl_float4) + sizeof(float)))  // floor: each sample's position and normal, a texel
      .launch(s.groups * kFitGroup, kFitGroup);
  return sumPartials(partial.download(ctx), kPenumbraBins);
}

// The `quantile` of a penumbra histogram: the bin's geometric centre (bin 0, which also holds the zeros, as 0), and
// the pixels counted.
PenumbraWidth penumbraQuantile(const Histogram& bins, double quantile) {
  if (!(quantile > 0.0 && quantile <= 1.0)) throw std::invalid_argument("penumbra histogram: quantile outside (0, 1]");
  PenumbraWidth width;
  width.pixels = bins.total;
  if (width.pixels == 0) return width;
  const size_t bin = quantileBin(bins, quantile);
  width.halfWidth =
      bin == 0 ? 0.0 : std::exp2((static_cast<double>(bin) + 0.5) / kSizeBinsPerOctave + kPenumbraLog2Min);
  return width;
}

PenumbraWidth penumbraQuantile(Context& ctx, const GBuffer& gbuffer, const Buffer<float>& map,
                               const Buffer<LightViewGpu>& view, const ReceiverBias& bias, double quantile,
                               PenumbraMeasure measure, float unit) {
  if (!(quantile > 0.0 && quantile <= 1.0)) throw std::invalid_argument("penumbra histogram: quantile outside (0, 1]");
  return penumbraQuantile(penumbraBins(ctx, gbuffer, map, view, bias, measure, unit), quantile);
}

}  // namespace

PenumbraWidth measurePenumbraWidth(Context& ctx, const GBuffer& gbuffer, const Buffer<float>& map,
                                   const Buffer<LightViewGpu>& view, const ReceiverBias& bias, double quantile) {
  return penumbraQuantile(ctx, gbuffer, map, view, bias, quantile, kHalfWidth, 1.0f);
}

OccluderDistance measureOccluderDistance(Context& ctx, const GBuffer& gbuffer, const Buffer<float>& map,
                                         const Buffer<LightViewGpu>& view, const ReceiverBias& bias, double quantile,
                                         float unit) {
  if (!(unit > 0.0f) || !std::isfinite(unit)) throw std::invalid_argument("measureOccluderDistance: unit must be > 0");
  const PenumbraWidth in = penumbraQuantile(ctx, gbuffer, map, view, bias, quantile, kDistance, unit);
  return {in.halfWidth * unit, in.pixels};
}

DepthRange reduceDepthRange(Context& ctx, const Buffer<float>& depth, size_t count) {
  DepthRange range{INFINITY, -INFINITY};
  if (count == 0) return range;
  const uint32_t chunk = chunkFor(ctx, count);
  const size_t groups = (count + chunk - 1) / chunk;
  Buffer<cl_float2> partial(ctx, groups);
  Kernel kernel(ctx, "kernels/fit.cl", "fit_depth_partial", "fit", ctx.info().cpuLayouts() ? "-DFIT_CONTIGUOUS=1" : "");
  kernel.args(depth, static_cast<uint32_t>(count), chunk, partial)
      .moves(count * sizeof(float))  // floor: read every depth once
      .launch(groups * kFitGroup, kFitGroup);
  for (const cl_float2& p : partial.download(ctx)) {
    range.min = std::min(range.min, p.s[0]);
    range.max = std::max(range.max, p.s[1]);
  }
  return range;
}

namespace {

// `h`'s counts added bin by bin to `sum` (empty: zeros).
void addBins(std::vector<uint64_t>& sum, const Histogram& h) {
  sum.resize(h.bins.size(), 0);
  for (size_t b = 0; b < h.bins.size(); ++b) sum[b] += h.bins[b];
}

Histogram withTotal(const std::vector<uint64_t>& bins) {
  Histogram h{bins};
  for (uint64_t b : h.bins) h.total += b;
  return h;
}

}  // namespace

void MapDetailMeter::add(Context& ctx, const GBuffer& gbuffer, const Buffer<float>& depth, int size,
                         const Buffer<LightViewGpu>& view, const ReceiverBias& bias, bool penumbrae) {
  if (penumbrae) addBins(penumbra_, penumbraBins(ctx, gbuffer, depth, view, bias, kHalfWidth, 1.0f));
  // Rows one a work-item, columns FIT_DETAIL_COLUMNS (8) a work-item and the last few together (kernels/fit.cl).
  const size_t lines = static_cast<size_t>(size) + static_cast<size_t>(size) / 8 + 1;
  const size_t groups = (lines + kFitGroup - 1) / kFitGroup;
  Buffer<uint32_t> partial(ctx, groups * kDetailBins);
  Kernel kernel(ctx, "kernels/fit.cl", "fit_detail_partial", "fit");
  kernel.args(depth, size, size, view, partial)
      .moves(2 * static_cast<uint64_t>(size) * static_cast<uint64_t>(size) * sizeof(float))  // rows, then columns
      .launch(groups * kFitGroup, kFitGroup);
  addBins(features_, sumPartials(partial.download(ctx), kDetailBins));
}

PenumbraWidth MapDetailMeter::penumbra(double quantile) const {
  return penumbraQuantile(withTotal(penumbra_), quantile);
}

uint64_t MapDetailMeter::features() const { return withTotal(features_).total; }

double MapDetailMeter::featureWidth(double quantile) const {
  const Histogram h = withTotal(features_);
  return h.total == 0 ? 0.0 : static_cast<double>(quantileBin(h, quantile) + 1);
}

ViewDepthRange tightViewDepth(Context& ctx, const GBuffer& g) {
  const DepthRange range = reduceDepthRange(ctx, g.depth, static_cast<size_t>(g.width) * g.height);
  ViewDepthRange r;
  if (range.min <= range.max && range.max > 0.0f) {
    r.far = range.max * 1.001f;
    r.near = std::clamp(range.min * 0.999f, r.far * 1e-5f, r.far * 0.999f);
  }
  return r;
}

}  // namespace penumbra
