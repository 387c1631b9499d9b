// Pyramid stage host wrapper: plans the level layout and the batches (levels per dispatch, tile, local
// memory; design in pyramid.h), then records one launch per batch, or one per level for the reference.
#include "host/stages/pyramid.h"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>

#include "host/cl/kernel.h"
#include "host/stages/moments.h"

namespace penumbra {
namespace {

const Range kLevelGroup(16, 8);  // per-level kernels
// The rows schedule (pyramid_minmax_rows, and pyramid_minmax_rows2 for two levels at once): a work-item per kRowTexels
// texels of a row (PYRAMID_ROW_TEXELS), up to kRowGroup of a row's work-items per group (PoCL runs them one after
// another: the source rows stream through).
constexpr uint32_t kRowTexels = 8, kRowGroup = 32;
constexpr uint32_t kBackgroundTile = 8;  // computeMinMaxLevels' backgroundTiles: texels a side (the rasterizer's tiles)

// Batched schedule per device type; a row counts only after tests/pyramid_schedule_test.cpp passes with it.
struct PyramidTuning {
  std::vector<uint32_t> tiles;  // tile edges the planner may choose from, largest first
  uint64_t localBytes;          // local memory budget per work-group (capped by the device's)
  uint32_t groupX, groupY;      // work-items per group, powers of two (narrowed for thin spans)
  uint32_t groupsPerUnit;       // the planner prefers tiles giving at least this many groups per compute unit
};
// GPUs: the whole 48 KiB and 1024 work-items, so that the few hundred groups of a first pass still fill the
// device (not yet timed on one: scripts/gpu-check.sh runs the schedule tests there).
const PyramidTuning kGpuTuning{{16, 8, 4}, 48 * 1024, 32, 32, 1};
// CPUs: one work-item per group, streaming its tile row by row (PoCL runs a group's work-items one after
// another, so strided work-items would revisit each cache line far apart in time: 16x16 groups ran 2x
// slower); 256 KiB of tile stays in L2.
const PyramidTuning kCpuTuning{{64, 32, 16, 8}, 256 * 1024, 1, 1, 4};
const PyramidTuning& tuning(const DeviceInfo& info) { return info.cpuLayouts() ? kCpuTuning : kGpuTuning; }

}  // namespace

std::string describePyramidTuning(const DeviceInfo& device) {
  const PyramidTuning& t = tuning(device);
  std::string tiles;
  for (uint32_t edge : t.tiles) tiles += fmt::format("{}{}", tiles.empty() ? "" : "/", edge);
  return fmt::format("{} (tiles {}, {} KiB per group, {}x{} work-items, {} groups per compute unit; min-max levels {})",
                     device.cpuLayouts() ? "cpu" : "gpu", tiles, t.localBytes / 1024, t.groupX, t.groupY,
                     t.groupsPerUnit, device.cpuLayouts() ? "by rows" : "batched");
}

namespace {

uint64_t texels(const PyramidLevel& l) { return uint64_t{l.width} * l.height; }

// A buffer of any element type as a kernel argument (Kernel::args takes what has get()): where one argument is one
// buffer or another, or a stand-in the kernel does not read.
struct AnyBuffer {
  const cl::Buffer& buffer;
  const cl::Buffer& get() const { return buffer; }
};

void checkNotRows(const PyramidConfig& config, const char* what) {
  if (config.schedule == PyramidSchedule::Rows)
    throw std::invalid_argument(
        fmt::format("pyramid: the rows schedule builds levels-only min-max pyramids, not {}", what));
}

// Halo of every level of a pass along one axis (PyramidBatch::haloX): level j + 1 of a tile reads level j
// up to twice its end, plus one texel where level j is odd.
std::vector<uint32_t> passHalos(const std::vector<PyramidLevel>& chain, const PyramidPass& p, bool y) {
  std::vector<uint32_t> halo(p.count, 0);
  for (int j = int(p.count) - 2; j >= 0; --j) {
    const uint32_t size = y ? chain[p.first + j].height : chain[p.first + j].width;
    halo[j] = 2 * halo[j + 1] + (size & 1);
  }
  return halo;
}

// The widest span (texels) of any work-group at level j of a pass along one axis (kernels/pyramid.cl
// pyramid_span): a group that is not the last computes its tile scaled plus the halo, the last one the rest.
uint32_t maxSpan(uint32_t size, uint32_t tile, uint32_t groups, uint32_t shift, uint32_t halo) {
  const uint32_t last = size - ((groups - 1) * tile << shift);
  return groups > 1 ? std::max(last, (tile << shift) + halo) : last;
}

// `count` levels from `first` with `tile`, its group counts and local buffers filled in.
PyramidPass makePass(const std::vector<PyramidLevel>& chain, uint32_t first, uint32_t count, uint32_t tile,
                     uint32_t texelBytes) {
  PyramidPass p{first, count, tile};
  const PyramidLevel& last = chain[first + count - 1];
  p.groupsX = (last.width + tile - 1) / tile, p.groupsY = (last.height + tile - 1) / tile;
  const std::vector<uint32_t> hx = passHalos(chain, p, false), hy = passHalos(chain, p, true);
  for (uint32_t j = 0; j + 1 < count; ++j) {  // the last level goes to global memory only
    const PyramidLevel& l = chain[first + j];
    const uint32_t shift = count - 1 - j;
    const uint64_t bytes = uint64_t{maxSpan(l.width, tile, p.groupsX, shift, hx[j])} *
                           maxSpan(l.height, tile, p.groupsY, shift, hy[j]) * texelBytes;
    uint64_t& buffer = j % 2 == 0 ? p.evenBytes : p.oddBytes;
    buffer = std::max(buffer, bytes);
  }
  return p;
}

}  // namespace

PyramidLayout pyramidLayout(uint32_t width, uint32_t height, uint32_t firstLevel) {
  checkShape({width, height, 1}, "pyramid");
  PyramidLayout layout;
  layout.firstLevel = firstLevel;
  if (width == 0 || height == 0) return layout;
  for (uint32_t level = 0;; ++level) {
    if (level >= firstLevel) {
      layout.levels.push_back({static_cast<uint32_t>(layout.texels), width, height, 0});
      layout.texels += size_t(width) * height;
    }
    if (width == 1 && height == 1) break;
    width = std::max(1u, width / 2);
    height = std::max(1u, height / 2);
  }
  return layout;
}

std::vector<PyramidPass> planPyramid(uint32_t width, uint32_t height, uint32_t texelBytes, uint64_t localBytes,
                                     const std::vector<uint32_t>& tiles, uint32_t minGroups) {
  if (tiles.empty() || std::find(tiles.begin(), tiles.end(), 0u) != tiles.end())
    throw std::invalid_argument("pyramid: tile edges must be positive");
  const std::vector<PyramidLevel> chain = pyramidLayout(width, height, 0).levels;
  std::vector<PyramidPass> passes;
  for (uint32_t first = 1; first < chain.size();) {
    const uint32_t most = std::min<uint32_t>(uint32_t(chain.size()) - first, PYRAMID_MAX_LEVELS - 1);
    std::vector<PyramidPass> fits;  // the passes of the most levels that fit, one per tile, largest tile first
    for (uint32_t count = most; count >= 1 && fits.empty(); --count)
      for (uint32_t tile : tiles) {
        const PyramidPass p = makePass(chain, first, count, tile, texelBytes);
        if (p.evenBytes + p.oddBytes <= localBytes) fits.push_back(p);
      }
    // Count 1 needs no local memory, so `fits` is never empty here.
    const auto enough = std::find_if(
        fits.begin(), fits.end(), [&](const PyramidPass& p) { return uint64_t{p.groupsX} * p.groupsY >= minGroups; });
    passes.push_back(enough != fits.end() ? *enough : fits.back());
    first += passes.back().count;
  }
  return passes;
}

namespace {

// A pass's work-group: groupX x groupY (powers of two), at most the kernel's limit, narrowed to a thin first
// level's span and widened along the other axis.
Range passGroup(uint32_t groupX, uint32_t groupY, size_t maxThreads, uint32_t spanX, uint32_t spanY) {
  const uint32_t threads = uint32_t(std::min<size_t>(size_t{groupX} * groupY, std::bit_floor(maxThreads)));
  uint32_t gx = std::min(groupX, threads), gy = threads / gx;
  if (spanX < gx) {
    gx = std::bit_ceil(spanX), gy = std::min(threads / gx, std::bit_ceil(spanY));
  } else if (spanY < gy) {
    gy = std::bit_ceil(spanY), gx = std::min(threads / gy, std::bit_ceil(spanX));
  }
  return Range(gx, gy);
}

// The kernel argument of pass `p` over `chain` (level 0 first, offsets into the pass's buffers).
PyramidBatch batchArgs(const std::vector<PyramidLevel>& chain, const PyramidPass& p) {
  PyramidBatch b{};
  b.src = chain[p.first - 1];
  const std::vector<uint32_t> hx = passHalos(chain, p, false), hy = passHalos(chain, p, true);
  for (uint32_t j = 0; j < p.count; ++j) b.level[j] = chain[p.first + j], b.haloX[j] = hx[j], b.haloY[j] = hy[j];
  b.count = p.count, b.tile = p.tile;
  return b;
}

// Records the passes over `chain`: the first with `first` reading `input` (level 0; min-max also writes
// level 0 to `out`), the others with `rest` reading `out`. Floor of a pass: its input level read once (at
// `inputBytes` per texel for the first), every level it writes written once.
// `firstExtra`: the first pass's arguments after those (computeMinMaxLevels' tiles).
template <class In, class Out, class... Extra>
std::vector<cl::Event> recordPasses(Context& ctx, Kernel& first, Kernel& rest, const Buffer<In>& input,
                                    Buffer<Out>& out, const std::vector<PyramidLevel>& chain,
                                    const std::vector<PyramidPass>& passes, uint32_t inputBytes, uint32_t texelBytes,
                                    bool writesLevel0, const PyramidConfig& config, const Extra&... firstExtra) {
  const PyramidTuning& row = tuning(ctx.info());
  const uint32_t groupX = std::bit_floor(config.groupX ? config.groupX : row.groupX);
  const uint32_t groupY = std::bit_floor(config.groupY ? config.groupY : row.groupY);
  std::vector<cl::Event> events;
  for (const PyramidPass& p : passes) {
    Kernel& kernel = p.first == 1 ? first : rest;
    const PyramidBatch b = batchArgs(chain, p);
    uint64_t bytes = texels(b.src) * (p.first == 1 ? inputBytes : texelBytes);
    if (p.first == 1 && writesLevel0) bytes += texels(b.src) * texelBytes;
    for (uint32_t j = 0; j < p.count; ++j) bytes += texels(b.level[j]) * texelBytes;
    const LocalMem even{std::max<uint64_t>(p.evenBytes, texelBytes)}, odd{std::max<uint64_t>(p.oddBytes, texelBytes)};
    if (p.first == 1)
      kernel.args(input, out, b, even, odd, firstExtra...);
    else
      kernel.args(out, out, b, even, odd);
    const Range group = passGroup(groupX, groupY, kernel.maxWorkGroupSize(),
                                  maxSpan(b.level[0].width, p.tile, p.groupsX, p.count - 1, b.haloX[0]),
                                  maxSpan(b.level[0].height, p.tile, p.groupsY, p.count - 1, b.haloY[0]));
    events.push_back(kernel.moves(bytes).launch(Range(p.groupsX * group.size[0], p.groupsY * group.size[1]), group));
  }
  return events;
}

std::vector<PyramidPass> plan(Context& ctx, uint32_t width, uint32_t height, uint32_t texelBytes,
                              const PyramidConfig& config) {
  const PyramidTuning& row = tuning(ctx.info());
  const uint64_t local = std::min(config.localBytes ? config.localBytes : row.localBytes, ctx.info().localMemBytes);
  const std::vector<uint32_t> tiles = config.tile ? std::vector<uint32_t>{config.tile} : row.tiles;
  return planPyramid(width, height, texelBytes, local, tiles, row.groupsPerUnit * ctx.info().computeUnits);
}

// Moment mips stored as T (float, or cl_half built with STORE_HALF). The plan sizes local memory for fp32 texels
// (what the kernels keep there); floors count the stored bytes.
template <class T>
std::vector<cl::Event> momentMips(Context& ctx, const Buffer<T>& base, const ImageShape& shape, Buffer<T>& mips,
                                  const PyramidConfig& config) {
  checkShape(shape, "pyramid");
  const PyramidLayout layout = pyramidLayout(shape.width, shape.height, 1);
  checkBufferSize(base.size(), shape.count(), "pyramid", "base level");
  checkBufferSize(mips.size(), layout.texels * shape.channels, "pyramid", "mip chain");
  const std::string options = fmt::format("-DPYRAMID_CHANNELS={} {}", shape.channels, storageOptions(storageOf<T>()));
  const uint32_t texelBytes = shape.channels * sizeof(T), localTexelBytes = shape.channels * sizeof(float);
  std::vector<PyramidLevel> chain{{0, shape.width, shape.height, 0}};  // level 0 in `base`, the rest in `mips`
  chain.insert(chain.end(), layout.levels.begin(), layout.levels.end());
  std::vector<cl::Event> events;
  checkNotRows(config, "moment mips");
  if (config.schedule == PyramidSchedule::PerLevel) {
    Kernel down(ctx, "kernels/pyramid.cl", "pyramid_downsample", "pyramid", options);
    for (size_t i = 1; i < chain.size(); ++i)  // floor: read the level above and write this one
      events.push_back(down.args(i == 1 ? base : mips, chain[i - 1], mips, chain[i])
                           .moves((texels(chain[i - 1]) + texels(chain[i])) * texelBytes)
                           .launch(Range(chain[i].width, chain[i].height), kLevelGroup));
    return events;
  }
  Kernel batch(ctx, "kernels/pyramid.cl", "pyramid_downsample_batch", "pyramid", options);
  return recordPasses(ctx, batch, batch, base, mips, chain,
                      plan(ctx, shape.width, shape.height, localTexelBytes, config), texelBytes, texelBytes, false,
                      config);
}

// ESM's log-space mips stored as T, level by level.
template <class T>
std::vector<cl::Event> logMomentMips(Context& ctx, const Buffer<T>& base, const ImageShape& shape, Buffer<T>& mips,
                                     float exponent) {
  checkShape(shape, "pyramid");
  if (shape.channels != 1) throw std::invalid_argument("pyramid: log-space mips have one channel");
  const PyramidLayout layout = pyramidLayout(shape.width, shape.height, 1);
  checkBufferSize(base.size(), shape.count(), "pyramid", "base level");
  checkBufferSize(mips.size(), layout.texels, "pyramid", "mip chain");
  std::vector<PyramidLevel> chain{{0, shape.width, shape.height, 0}};  // level 0 in `base`, the rest in `mips`
  chain.insert(chain.end(), layout.levels.begin(), layout.levels.end());
  Kernel down(ctx, "kernels/pyramid.cl", "pyramid_downsample_log", "pyramid",
              fmt::format("-DPYRAMID_CHANNELS=1 {}", storageOptions(storageOf<T>())));
  std::vector<cl::Event> events;
  for (size_t i = 1; i < chain.size(); ++i)  // floor: read the level above and write this one
    events.push_back(down.args(i == 1 ? base : mips, chain[i - 1], mips, chain[i], exponent)
                         .moves((texels(chain[i - 1]) + texels(chain[i])) * sizeof(T))
                         .launch(Range(chain[i].width, chain[i].height), kLevelGroup));
  return events;
}

}  // namespace

std::vector<cl::Event> computeLogMomentMips(Context& ctx, const Buffer<float>& base, const ImageShape& shape,
                                            Buffer<float>& mips, float exponent) {
  return logMomentMips(ctx, base, shape, mips, exponent);
}

std::vector<cl::Event> computeLogMomentMips(Context& ctx, const Buffer<cl_half>& base, const ImageShape& shape,
                                            Buffer<cl_half>& mips, float exponent) {
  return logMomentMips(ctx, base, shape, mips, exponent);
}

std::vector<cl::Event> computeMomentMips(Context& ctx, const Buffer<float>& base, const ImageShape& shape,
                                         Buffer<float>& mips, const PyramidConfig& config) {
  return momentMips(ctx, base, shape, mips, config);
}

std::vector<cl::Event> computeMomentMips(Context& ctx, const Buffer<cl_half>& base, const ImageShape& shape,
                                         Buffer<cl_half>& mips, const PyramidConfig& config) {
  return momentMips(ctx, base, shape, mips, config);
}

std::vector<cl::Event> computeMinMaxPyramid(Context& ctx, const Buffer<float>& depth, uint32_t width, uint32_t height,
                                            Buffer<cl_float2>& out, const PyramidConfig& config) {
  const PyramidLayout layout = pyramidLayout(width, height, 0);
  checkBufferSize(depth.size(), size_t(width) * height, "pyramid", "depth");
  checkBufferSize(out.size(), layout.texels, "pyramid", "min-max pyramid");
  const std::vector<PyramidLevel>& chain = layout.levels;
  checkNotRows(config, "min-max pyramids with level 0");
  if (chain.empty()) return {};
  const std::string fromDepth = "-DPYRAMID_MINMAX=1 -DPYRAMID_FROM_DEPTH=1", fromLevels = "-DPYRAMID_MINMAX=1";
  const auto texelBytes = uint32_t(sizeof(cl_float2));
  std::vector<cl::Event> events;
  if (config.schedule == PyramidSchedule::PerLevel || chain.size() == 1) {  // a 1x1 map has only level 0
    // Floors: the base reads the depth map and writes level 0; each further level reads the level above.
    Kernel base(ctx, "kernels/pyramid.cl", "pyramid_minmax_base", "pyramid", fromDepth);
    events.push_back(base.args(depth, out, chain[0])
                         .moves(texels(chain[0]) * (sizeof(float) + texelBytes))
                         .launch(Range(width, height), kLevelGroup));
    if (chain.size() == 1) return events;
    Kernel down(ctx, "kernels/pyramid.cl", "pyramid_minmax_down", "pyramid", fromLevels);
    for (size_t i = 1; i < chain.size(); ++i)
      events.push_back(down.args(out, chain[i - 1], out, chain[i])
                           .moves((texels(chain[i - 1]) + texels(chain[i])) * texelBytes)
                           .launch(Range(chain[i].width, chain[i].height), kLevelGroup));
    return events;
  }
  const std::vector<PyramidPass> passes = plan(ctx, width, height, texelBytes, config);
  Kernel first(ctx, "kernels/pyramid.cl", "pyramid_minmax_batch", "pyramid", fromDepth);
  std::optional<Kernel> rest;  // passes after the first read float2 levels: another build, only when needed
  if (passes.size() > 1) rest.emplace(ctx, "kernels/pyramid.cl", "pyramid_minmax_batch", "pyramid", fromLevels);
  return recordPasses(ctx, first, rest ? *rest : first, depth, out, chain, passes, uint32_t(sizeof(float)), texelBytes,
                      true, config);
}

cl_float2 computeMinMaxLevels(Context& ctx, const Buffer<float>& depth, uint32_t width, uint32_t height,
                              Buffer<cl_float2>& out, const PyramidConfig& config,
                              const Buffer<uint32_t>* backgroundTiles, Buffer<uint32_t>* kept) {
  if (config.schedule == PyramidSchedule::PerLevel)
    throw std::invalid_argument("pyramid: levels-only min-max pyramids have the batched schedule only");
  const PyramidLayout layout = pyramidLayout(width, height, 1);
  checkBufferSize(depth.size(), size_t(width) * height, "pyramid", "depth");
  checkBufferSize(out.size(), std::max<size_t>(layout.texels, 1), "pyramid", "min-max levels");
  // The first launch's tiles taken as background (kernels/pyramid.cl pyramid_reduce_depth); 0: none, and the depth map
  // stands in for the argument, unread.
  const uint32_t tilesX = backgroundTiles != nullptr ? (width + kBackgroundTile - 1) / kBackgroundTile : 0u;
  if (tilesX != 0)
    checkBufferSize(backgroundTiles->size(), size_t{tilesX} * ((height + kBackgroundTile - 1) / kBackgroundTile),
                    "pyramid", "background tiles");
  const AnyBuffer tiles{tilesX != 0 ? backgroundTiles->get() : depth.get()};
  if (layout.levels.empty()) {  // 1x1: the map is the whole pyramid
    const float z = depth.download(ctx)[0];
    const bool background = tilesX != 0 && backgroundTiles->download(ctx, 0, 1)[0] != 0;
    return std::isfinite(z) && !background ? cl_float2{{z, z}} : cl_float2{{INFINITY, INFINITY}};
  }
  std::vector<PyramidLevel> chain{{0, width, height, 0}};  // level 0 in `depth`, the rest in `out`
  chain.insert(chain.end(), layout.levels.begin(), layout.levels.end());
  const auto texelBytes = uint32_t(sizeof(cl_float2));
  const std::string fromDepth = "-DPYRAMID_MINMAX=1 -DPYRAMID_FROM_DEPTH=2", fromLevels = "-DPYRAMID_MINMAX=1";
  const bool rows =
      config.schedule == PyramidSchedule::Rows || (config.schedule == PyramidSchedule::Auto && ctx.info().cpuLayouts());
  if (rows) {
    std::optional<Kernel> first, rest, first2, rest2;  // one level a launch, or two (pyramid_minmax_rows2)
    const auto kernel = [&](std::optional<Kernel>& k, const char* name, const std::string& options) -> Kernel& {
      if (!k) k.emplace(ctx, "kernels/pyramid.cl", name, "pyramid", options);
      return *k;
    };
    for (size_t i = 1; i < chain.size();) {  // floor: read the level above and write the new ones
      const PyramidLevel& source = chain[i - 1];
      const uint64_t sourceBytes = texels(source) * (i == 1 ? sizeof(float) : texelBytes);
      // Both halvings exact, and the second level's rows whole vectors: two levels, the first not read back.
      if (i + 1 < chain.size() && source.width % (4 * kRowTexels) == 0 && source.height % 4 == 0) {
        Kernel& k = i == 1 ? kernel(first2, "pyramid_minmax_rows2", fromDepth)
                           : kernel(rest2, "pyramid_minmax_rows2", fromLevels);
        // The first launch skips the background tiles' reads, and their writes where `kept` says the levels hold
        // them; keep 0: no state, and the depth map stands in for its argument, unread.
        const uint32_t items = chain[i + 1].width / kRowTexels;
        const int keep = i == 1 && kept != nullptr ? 1 : 0;
        if (keep) checkBufferSize(kept->size(), size_t{items} * chain[i + 1].height, "pyramid", "kept background");
        const AnyBuffer input{i == 1 ? depth.get() : out.get()};
        const AnyBuffer keptState{keep ? kept->get() : depth.get()};
        k.args(input, source, out, chain[i], chain[i + 1], tiles, i == 1 ? tilesX : 0u, keptState, keep);
        k.moves(sourceBytes + (texels(chain[i]) + texels(chain[i + 1])) * texelBytes)
            .launch(Range(items, chain[i + 1].height), Range(std::min(kRowGroup, std::bit_ceil(items)), 1));
        i += 2;
        continue;
      }
      Kernel& k =
          i == 1 ? kernel(first, "pyramid_minmax_rows", fromDepth) : kernel(rest, "pyramid_minmax_rows", fromLevels);
      if (i == 1)
        k.args(depth, source, out, chain[i], tiles, tilesX);
      else
        k.args(out, source, out, chain[i], tiles, 0u);
      const uint32_t items = (chain[i].width + kRowTexels - 1) / kRowTexels;
      k.moves(sourceBytes + texels(chain[i]) * texelBytes)
          .launch(Range(items, chain[i].height), Range(std::min(kRowGroup, std::bit_ceil(items)), 1));
      ++i;
    }
  } else {
    const std::vector<PyramidPass> passes = plan(ctx, width, height, texelBytes, config);
    Kernel first(ctx, "kernels/pyramid.cl", "pyramid_minmax_batch", "pyramid", fromDepth);
    std::optional<Kernel> rest;
    if (passes.size() > 1) rest.emplace(ctx, "kernels/pyramid.cl", "pyramid_minmax_batch", "pyramid", fromLevels);
    recordPasses(ctx, first, rest ? *rest : first, depth, out, chain, passes, uint32_t(sizeof(float)), texelBytes,
                 false, config, tiles, tilesX);
  }
  return out.download(ctx, layout.levels.back().offset, 1)[0];
}

void MinMaxLevels::allocate(Context& ctx, uint32_t width, uint32_t height) {
  if (!pyramid_.empty() && width == width_ && height == height_) return;
  const PyramidLayout layout = pyramidLayout(width, height, 1);
  pyramid_.allocate(ctx, std::max<size_t>(layout.texels, 1));
  levels_ = layout.levels.empty()
                ? Buffer<PyramidLevel>(ctx, 1, CL_MEM_READ_ONLY)  // a 1x1 map: the map alone
                : Buffer<PyramidLevel>(ctx, std::span<const PyramidLevel>(layout.levels), CL_MEM_READ_ONLY);
  count_ = static_cast<uint32_t>(layout.levels.size());
  width_ = width, height_ = height;
  // The first two-level launch's work-items (a map whose sides take it: computeMinMaxLevels' test; one entry
  // otherwise), none holding a kept background yet.
  const bool twoLevels = width % (4 * kRowTexels) == 0 && height % 4 == 0;
  kept_.allocate(ctx, twoLevels ? std::max<size_t>(size_t{width / (4 * kRowTexels)} * (height / 4), 1) : 1);
  kept_.fill(ctx, 0u);
}

cl_float2 MinMaxLevels::build(Context& ctx, const Buffer<float>& depth, uint32_t width, uint32_t height,
                              const Buffer<uint32_t>* backgroundTiles) {
  allocate(ctx, width, height);
  return computeMinMaxLevels(ctx, depth, width, height, pyramid_, {}, backgroundTiles, &kept_);
}

}  // namespace penumbra
