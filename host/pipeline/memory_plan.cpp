// The frame's memory plan: per-stage byte counts from the image size and the techniques' parameters, summed and
// checked against the device's limits before the first allocation (docs/robustness.md, "Memory plan").
#include "host/pipeline/memory_plan.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <numeric>
#include <utility>

#include "host/pipeline/map_size.h"
#include "kernels/shared/izb.h"

namespace penumbra {
namespace {

// G-buffer: depth 4 + position 16 + normal 16 + triangle id 4 + object id 4 (raster/rasterizer.h GBuffer), plus the
// rasterizer's own depth and id targets of the camera pass (8).
constexpr uint64_t kGBufferBytesPerPixel = 44 + 8;
constexpr uint64_t kPreviewBytesPerPixel = 16;    // shade_preview's float4 RGBA
constexpr uint64_t kVisibilityBytesPerPixel = 4;  // per light
// A technique's per-pixel buffers (MomentDebug's moments and statistics, the split AOVs, jittered's state, PCSS's
// blocker depths): at most 32 bytes per pixel in every technique of the registry.
constexpr uint64_t kTechniquePixelBytes = 32;
// Each shadow-map texel: the rasterizer's depth and triangle id targets (depth-only maps use half: an upper bound).
constexpr uint64_t kMapTexelBytes = 8;
// Host: the image's channels (R, G, B, A; P.*, N.*, depth.Z; visibility.Y and a layer per light; the debug channels,
// at most 4 floats) and the 8-bit RGBA preview, those the frame's FrameOutputs keep.
constexpr uint64_t kPreviewFloatsPerPixel = 4, kSurfaceFloatsPerPixel = 7, kDebugFloatsPerPixel = 4;
constexpr uint64_t kPreviewPngBytesPerPixel = 4;

double param(const PlannedLight& light, const char* name, double fallback) {
  return light.params->has(name) ? light.params->get(name) : fallback;
}

// izb (host/techniques/izb.cpp) draws no map: its light grid holds 16 bytes per 8x8-texel cell (count, start,
// cursor, farthest depth), 8 more under an area light (its caster lists' count and start; planned whatever the light,
// since the plan does not see its radius) and 8 per tile of IZB_TILE_CELLS^2 cells (the clusters' tile lists' count
// and start) with the light pattern's bitmask tables (at most 1 MiB), 68 bytes per
// triangle slot, the triangles padded to whole clusters of IZB_CLUSTER (each caster's record: ball, vertices, plane;
// and its triangle), 48 per cluster (its ball and its box), and each pass 8 bytes per sample (cell, sorted index) of at
// most
// --izb-chunk samples. The casters' entries (in the hard case the rasterizer's tile lists, under an area light izb's
// own) are grown to what a pass asks for, as the rasterizer's queues are. The cube faces of a point light reuse them.
MemoryStage izbGrid(const PlannedLight& light, size_t index, uint64_t pixels, uint64_t triangles) {
  MemoryStage stage{fmt::format("light {} ({}): grid and samples", index, light.technique->name)};
  const auto cellsPerSide = static_cast<uint64_t>((param(light, "map-size", 8) + 7) / 8);
  const uint64_t samples =
      pixels * static_cast<uint64_t>(izb_samples_of_choice(light.params->getInt("izb-samples")));
  const uint64_t chunk = std::min(samples, static_cast<uint64_t>(param(light, "izb-chunk", 1 << 24)));
  const auto lightPoints = static_cast<uint64_t>(param(light, "izb-light-samples", 16));
  const uint64_t tables = uint64_t{IZB_MASK_ANGLES} * IZB_MASK_OFFSETS * 2 * 4 * ((lightPoints + 31) / 32);
  const uint64_t clusters = (triangles + IZB_CLUSTER - 1) / IZB_CLUSTER, slots = clusters * IZB_CLUSTER;
  stage.largestBuffer = std::max({chunk * 4, cellsPerSide * cellsPerSide * 4, tables, slots * 64});
  const uint64_t tilesPerSide = izb_tiles_of(static_cast<uint32_t>(cellsPerSide));
  stage.deviceBytes = cellsPerSide * cellsPerSide * 24 + tilesPerSide * tilesPerSide * 8 + chunk * 8 + tables +
                      slots * 68 + clusters * 48;
  return stage;
}

// A technique's maps: depth targets, moments (4 channels of fp32 or fp16 at most), the blur's scratch and the mip
// chain (a third more), for each split or layer and each cube face of a point light.
MemoryStage techniqueMaps(const PlannedLight& light, size_t index, uint64_t pixels) {
  MemoryStage stage{fmt::format("light {} ({}): maps", index, light.technique->name)};
  // --map-size auto (0): planned at the largest size it may choose.
  const double size = param(light, "map-size", 0) == 0 ? param(light, "map-size-max", 0) : param(light, "map-size", 0);
  const double side = size + (light.type == LightType::Point ? 2 * param(light, "cube-guard", 0) : 0);
  const auto texels = static_cast<uint64_t>(side * side);
  const uint64_t faces = light.type == LightType::Point ? 6 : 1;
  const auto layers = static_cast<uint64_t>(std::max(
      {1.0, param(light, "pssm-splits", 1), param(light, "lvsm-layers", 1), param(light, "pssm-max-splits", 1)}));
  uint64_t perTexel = kMapTexelBytes;
  if (light.params->has("moment-storage") || light.params->has("lvsm-storage") || light.params->has("sat-precision") ||
      light.params->has("vssm-sat")) {
    const uint64_t moments = param(light, "moment-storage", 0) == 1 ? 8 : 16;  // fp16 halves the four channels
    const bool blurred = param(light, "blur-radius", 0) != 0, trilinear = param(light, "moment-filtering", 0) == 1;
    perTexel += moments * (blurred ? 2 : 1) + (trilinear ? moments * 2 / 3 + 1 : 0);  // mips: 1/3 of both copies
  }
  stage.largestBuffer = texels * layers * std::max<uint64_t>(perTexel - kMapTexelBytes, 4);
  stage.deviceBytes = texels * layers * perTexel * faces;
  if (param(light, "map-size", 0) == 0)  // auto: the drawn probe (host/pipeline/map_size.h)
    stage.deviceBytes += uint64_t{kMapProbeSize} * kMapProbeSize * kMapTexelBytes;
  if (light.params->has("fvsm-budget")) {
    // fvsm: its atlas (faces reuse it) holds at most the budget, the whole virtual map, or a tile per pixel (every
    // tile drawn holds a pixel).
    const double virtualSide = param(light, "fvsm-max-size", 0);
    const auto atlas = static_cast<uint64_t>(std::min({param(light, "fvsm-budget", 0), virtualSide * virtualSide,
                                                       static_cast<double>(pixels) * size * size}));
    stage.largestBuffer = atlas * 4;
    stage.deviceBytes = atlas * kMapTexelBytes;
  }
  return stage;
}

}  // namespace

uint64_t MemoryPlan::deviceBytes() const {
  return std::accumulate(stages.begin(), stages.end(), uint64_t{0},
                         [](uint64_t sum, const MemoryStage& s) { return sum + s.deviceBytes; });
}

uint64_t MemoryPlan::hostBytes() const {
  return std::accumulate(stages.begin(), stages.end(), uint64_t{0},
                         [](uint64_t sum, const MemoryStage& s) { return sum + s.hostBytes; });
}

const MemoryStage& MemoryPlan::largest() const {
  if (stages.empty()) throw std::logic_error("MemoryPlan::largest: no stages");
  return *std::max_element(stages.begin(), stages.end(),
                           [](const MemoryStage& a, const MemoryStage& b) { return a.deviceBytes < b.deviceBytes; });
}

std::string MemoryPlan::describe() const {
  std::string out;
  for (const MemoryStage& s : stages)
    out += fmt::format("{}{} {}", out.empty() ? "" : ", ", s.name,
                       s.deviceBytes ? formatBytes(s.deviceBytes) : formatBytes(s.hostBytes) + " on the host");
  return out;
}

// The rasterizer's buffers for `scene`: positions and normals (12 bytes each a vertex), triangles, object ids and
// material bits (20 bytes a triangle), set-up records (RasterTriangle, 64 bytes, for every triangle and an eighth more
// for clipping fans), the bin queue (two 4-byte entries, 2 a triangle) and the tile queue (4 a triangle and 2 a
// tile of the largest view, here the frame's): sizeQueues' first estimates.
MemoryStage rasterizerStage(const PlannedScene& scene, uint64_t pixels) {
  if (scene.triangles == 0) return {"rasterizer", 0, 0, 0};
  const uint64_t t = scene.triangles, records = t + 1024 + t / 8, binEntries = 4096 + 2 * t;
  const uint64_t tileEntries = 16384 + 4 * t + 2 * (pixels / 64);
  MemoryStage stage{"rasterizer: scene and queues"};
  stage.deviceBytes = scene.vertices * 24 + t * 20 + records * 64 + binEntries * 8 + tileEntries * 4;
  stage.largestBuffer = std::max({records * 64, tileEntries * 4, t * 12, scene.vertices * 12});
  return stage;
}

MemoryPlan planFrame(const Camera& camera, const std::vector<PlannedLight>& lights, FrameDownload download,
                     PlannedScene scene, FrameOutputs outputs) {
  const uint64_t pixels = static_cast<uint64_t>(camera.width) * static_cast<uint64_t>(camera.height);
  MemoryPlan plan;
  plan.stages.push_back({"G-buffer", pixels * kGBufferBytesPerPixel, 0, pixels * 16});
  if (scene.triangles > 0) plan.stages.push_back(rasterizerStage(scene, pixels));
  for (size_t i = 0; i < lights.size(); ++i) {
    const uint64_t perPixel =
        kVisibilityBytesPerPixel + kTechniquePixelBytes + (lights[i].type == LightType::Point ? 4 : 0);
    plan.stages.push_back({fmt::format("light {} ({}): per-pixel buffers", i, lights[i].technique->name),
                           pixels * perPixel, 0, pixels * 16});
    plan.stages.push_back(lights[i].params->has("izb-samples") ? izbGrid(lights[i], i, pixels, scene.triangles)
                                                               : techniqueMaps(lights[i], i, pixels));
  }
  if (outputs.preview)
    plan.stages.push_back({"shade", pixels * (kPreviewBytesPerPixel + (lights.size() > 1 ? 4 : 0)), 0, pixels * 16});
  const uint64_t floats = (outputs.preview ? kPreviewFloatsPerPixel : 0) +
                          (outputs.surfaces ? kSurfaceFloatsPerPixel : 0) + (outputs.debug ? kDebugFloatsPerPixel : 0) +
                          1 + lights.size();
  const uint64_t whole = pixels * (floats * 4 + (outputs.preview ? kPreviewPngBytesPerPixel : 0));
  plan.stages.push_back(
      {"image download", 0, download == FrameDownload::Image ? whole : std::min(whole, kDeferredHostBytes), 0});
  return plan;
}

void checkMemoryPlan(const MemoryPlan& plan, const DeviceInfo& device, std::optional<uint64_t> limit) {
  const uint64_t global = limit ? std::min(*limit, device.globalMemBytes) : device.globalMemBytes;
  const std::string source = limit && *limit < device.globalMemBytes ? "--memory-limit" : "the device's global memory";
  const MemoryStage& big = plan.largest();
  if (plan.deviceBytes() > global)
    throw MemoryError(fmt::format("the frame needs {} of device memory, more than {} ({}); the most: {} {} ({})",
                                  formatBytes(plan.deviceBytes()), formatBytes(global), source, big.name,
                                  formatBytes(big.deviceBytes), plan.describe()));
  if (limit && plan.hostBytes() > *limit)
    throw MemoryError(fmt::format("the frame needs {} of host memory to read back, more than {} (--memory-limit)",
                                  formatBytes(plan.hostBytes()), formatBytes(*limit)));
  for (const MemoryStage& s : plan.stages)
    if (s.largestBuffer > device.maxAllocBytes)
      throw MemoryError(fmt::format("{} needs one buffer of {}, more than the device's largest allocation {}", s.name,
                                    formatBytes(s.largestBuffer), formatBytes(device.maxAllocBytes)));
}

std::string formatBytes(uint64_t bytes) {
  static constexpr const char* kUnits[] = {"KiB", "MiB", "GiB", "TiB"};
  if (bytes < 1024) return fmt::format("{} bytes", bytes);
  double value = static_cast<double>(bytes) / 1024.0;
  int unit = 0;
  while (value >= 1024.0 && unit < 3) value /= 1024.0, ++unit;
  return fmt::format("{:.{}f} {}", value, value < 10.0 ? 1 : 0, kUnits[unit]);
}

uint64_t parseMemorySize(std::string_view text, std::string_view what) {
  const auto bad = [&](const char* why) {
    throw std::invalid_argument(fmt::format("{} \"{}\": {} (e.g. 4GiB, 512MiB, 1.5G)", what, text, why));
  };
  double value = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end == text.data()) bad("expected a number of bytes with an optional unit");
  std::string unit(end, text.data() + text.size());
  std::transform(unit.begin(), unit.end(), unit.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  static constexpr std::pair<const char*, double> kUnits[] = {
      {"", 1.0},       {"b", 1.0},     {"k", 0x1p10},   {"kb", 0x1p10}, {"kib", 0x1p10},
      {"m", 0x1p20},   {"mb", 0x1p20}, {"mib", 0x1p20}, {"g", 0x1p30},  {"gb", 0x1p30},
      {"gib", 0x1p30}, {"t", 0x1p40},  {"tb", 0x1p40},  {"tib", 0x1p40}};
  const auto it = std::find_if(std::begin(kUnits), std::end(kUnits), [&](const auto& u) { return unit == u.first; });
  if (it == std::end(kUnits)) bad("unknown unit");
  const double bytes = value * it->second;
  if (!(bytes >= 1.0) || !(bytes < 0x1p63)) bad("must be at least 1 byte and below 8 EiB");
  return static_cast<uint64_t>(bytes);
}

}  // namespace penumbra
