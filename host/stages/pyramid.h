// Pyramid stage: mip chains of moment images (exact area averages; odd sizes keep the mean) and the
// min-max depth pyramid of a hierarchical shadow map (VSSM). Batched: each dispatch computes several
// consecutive levels, so 2048^2 and 4096^2 take 2 dispatches (4-channel mips 3) instead of 11-13.
// Kernels: kernels/pyramid.cl; layout and ownership: kernels/shared/pyramid.h (PyramidBatch).
//
// Design. A work-group owns a T x T tile of a pass's last level and computes it from the pass's input level
// (global memory) through local memory. k levels up the tile is T 2^k texels plus a halo where sizes are
// odd (3-tap footprints): halo_k = 2 halo_(k-1) + 1, at most 2^k - 1, so spans are <= 2^k (T + 1) - 1;
// powers of two need none. Two ping-pong local buffers hold level j (read) and j + 1 (written). The planner
// takes per pass the most levels K whose buffers fit the local memory (exact spans, clipped at the level
// sizes) for some tile edge of the device's row, then the largest such tile still giving a group per
// compute unit (else the one with the most groups); once the rest of the chain fits one group, that group
// loops over all remaining levels (the tail). GPU row (48 KiB, 1024 work-items): float2 2048^2 is K = 5
// with T = 4 (256 groups, 40 KiB) then levels 6-11 in one group; 4096^2 is K = 5 (1024 groups) then 6-12.
// Min-max folds level 0 (the converted depth map) into its first pass, so the depth map is read once.
// Results equal the per-level schedule bit for bit: the same taps, weights and summation order through one
// shared per-texel function (tests/pyramid_schedule_test.cpp).
//
// Not folded: the tail into the last work-group of the previous pass (AMD SPD's atomic counter). OpenCL 1.2
// promises no memory consistency between the work-groups of one launch (sec. 3.3.1), so that group could
// read stale texels of the others; the separate tail costs one launch.
#pragma once

#include <CL/opencl.hpp>
#include <cstdint>
#include <string>
#include <vector>

#include "host/cl/buffer.h"
#include "host/cl/context.h"
#include "host/stages/image_shape.h"
#include "kernels/shared/pyramid.h"

namespace penumbra {

// Levels `firstLevel`.. down to 1x1 of a width x height base: levels[i] is level firstLevel + i, with
// offsets (in texels) into one buffer of `texels` texels.
struct PyramidLayout {
  uint32_t firstLevel = 0;
  std::vector<PyramidLevel> levels;
  size_t texels = 0;
};
PyramidLayout pyramidLayout(uint32_t width, uint32_t height, uint32_t firstLevel);

// Batched: several levels per dispatch (moment mips ~15% faster than PerLevel on PoCL too); PerLevel: one launch
// per level, the reference schedule the batches are tested against bit for bit; Rows (computeMinMaxLevels only): one
// launch per level, or per two where both halvings are exact, a work-item per 8 texels of a row read as explicit
// vectors, which CPUs vectorize (PoCL, 2-core EPYC: 4096^2 levels 17.0 -> 3.0 ms; docs/performance.md); Auto: Rows for
// computeMinMaxLevels on CPU devices (DeviceInfo::cpuLayouts), else Batched.
enum class PyramidSchedule { Auto, Batched, PerLevel, Rows };

struct PyramidConfig {
  PyramidSchedule schedule = PyramidSchedule::Auto;
  // 0 everywhere: the device's row (pyramid.cpp). tile: a work-group's tile edge in every pass; localBytes:
  // the local memory a work-group may use (at most the device's); groupX x groupY: work-items per group.
  uint32_t tile = 0;
  uint64_t localBytes = 0;
  uint32_t groupX = 0, groupY = 0;
};

// One dispatch of the batched schedule: output levels [first, first + count) of the full chain (level 0 =
// the base) from level first - 1, by groupsX x groupsY work-groups of `tile`^2 texels of the last level.
struct PyramidPass {
  uint32_t first = 1, count = 0, tile = 0;
  uint32_t groupsX = 0, groupsY = 0;
  uint64_t evenBytes = 0, oddBytes = 0;  // the two local buffers (level parity within the pass)
};

// The batched schedule's row for `device` in words (tile edges, local memory per group, work-items per group, groups
// per compute unit): what `penumbra selftest` reports of the per-device table.
std::string describePyramidTuning(const DeviceInfo& device);

// The passes for a width x height base and texels of `texelBytes` bytes, under `localBytes` of local memory
// per work-group, over the tile edges `tiles` (largest first), preferring the largest tile that still
// gives `minGroups` work-groups. Throws std::invalid_argument when no tile fits one level.
std::vector<PyramidPass> planPyramid(uint32_t width, uint32_t height, uint32_t texelBytes, uint64_t localBytes,
                                     const std::vector<uint32_t>& tiles, uint32_t minGroups);

// Mip levels 1.. of `base` (shape.count() floats, level 0) into `mips` (pyramidLayout(w, h, 1).texels *
// channels floats). Launches "pyramid/pyramid_downsample_batch" (PerLevel: "pyramid/pyramid_downsample",
// one per level).
std::vector<cl::Event> computeMomentMips(Context& ctx, const Buffer<float>& base, const ImageShape& shape,
                                         Buffer<float>& mips, const PyramidConfig& config = {});
// The same from and into half moments (MomentStorage::Float16): texels are read as half, averaged in fp32 exactly
// as above and stored rounded to nearest even (the kernels built with STORE_HALF); local memory stays fp32.
std::vector<cl::Event> computeMomentMips(Context& ctx, const Buffer<cl_half>& base, const ImageShape& shape,
                                         Buffer<cl_half>& mips, const PyramidConfig& config = {});
// ESM's mips in log space (one channel; kernels/shared/moments.h moments_log_mix): each level's D has e^(c D) the
// area average of the level above's e^(c D), over computeMomentMips' footprints, per level
// ("pyramid/pyramid_downsample_log"). fp32 or half, as above.
std::vector<cl::Event> computeLogMomentMips(Context& ctx, const Buffer<float>& base, const ImageShape& shape,
                                            Buffer<float>& mips, float exponent);
std::vector<cl::Event> computeLogMomentMips(Context& ctx, const Buffer<cl_half>& base, const ImageShape& shape,
                                            Buffer<cl_half>& mips, float exponent);

// Levels 0.. of the min-max pyramid of `depth` (width*height light depths) into `out`
// (pyramidLayout(w, h, 0).texels float2 (min, max)). Background and NaN texels are the empty interval
// (+INFINITY, -INFINITY), so they never widen a range. Launches "pyramid/pyramid_minmax_*".
std::vector<cl::Event> computeMinMaxPyramid(Context& ctx, const Buffer<float>& depth, uint32_t width, uint32_t height,
                                            Buffer<cl_float2>& out, const PyramidConfig& config = {});

// Levels 1.. only of the min-max pyramid of `depth` into `out` (pyramidLayout(w, h, 1).texels float2, at least one):
// level 0 stays the depth map, which lookups read beside them (kernels/shared/pyramid.h pyramid_depth_range_of), so
// the first pass writes half the bytes computeMinMaxPyramid's does. Background and NaN texels are the farthest depth
// (+INFINITY, +INFINITY): a minimum ignores them, a maximum says nothing occludes there. Batched only (a PerLevel
// config throws std::invalid_argument). Returns the last level, 1x1: (min, max) over the whole map, waiting for it
// (a 1x1 map: its texel). Launches "pyramid/pyramid_minmax_batch". `backgroundTiles` (optional): nonzero per 8x8 tile
// of the map, row-major from row 0, whose texels the levels take as background, in every schedule: the rasterizer's
// RasterTargets::backgroundTiles, which hold only background (the levels are then the same bit for bit as without
// them), or its RasterTargets::casterFreeTiles, which no caster reaches (a min-max pyramid of the casters alone over
// a map that keeps its receivers). The rows schedule's first launch writes blocks of such tiles without reading them
// (a shadow map of casters alone is mostly background: scenes/default.json's 4096^2 map for pcss, 96 % of its tiles).
// `kept` (optional): state between builds into the same `out`, which nothing else may write, one entry per
// work-item of that launch ((width / 32) x (height / 4), zero before the first build): nonzero where `out` already
// holds its 32 x 4 texels' background, which is then not written again either; a build without `backgroundTiles`
// writes every block and clears it.
cl_float2 computeMinMaxLevels(Context& ctx, const Buffer<float>& depth, uint32_t width, uint32_t height,
                              Buffer<cl_float2>& out, const PyramidConfig& config = {},
                              const Buffer<uint32_t>* backgroundTiles = nullptr, Buffer<uint32_t>* kept = nullptr);

// computeMinMaxLevels' output with its layout on the device, reallocated only when the map's size changes: what a
// kernel's pyramid_depth_range_of reads beside the map (pcss's adaptive search, vssm's HSM). Before the first
// allocate() or build() the buffers are empty.
class MinMaxLevels {
 public:
  // Buffers for a width x height map (at least one element each, so that a 1x1 map, which has no level above it,
  // still passes kernel arguments).
  void allocate(Context& ctx, uint32_t width, uint32_t height);
  // allocate, then computeMinMaxLevels (with the tiles taken as background where given, and what the builds before
  // left as background): the map's (min, max), of the texels not taken as background.
  cl_float2 build(Context& ctx, const Buffer<float>& depth, uint32_t width, uint32_t height,
                  const Buffer<uint32_t>* backgroundTiles = nullptr);
  const Buffer<cl_float2>& pyramid() const { return pyramid_; }
  const Buffer<PyramidLevel>& levels() const { return levels_; }
  uint32_t count() const { return count_; }  // levels above the map

 private:
  Buffer<cl_float2> pyramid_;
  Buffer<PyramidLevel> levels_;
  Buffer<uint32_t> kept_;  // computeMinMaxLevels' `kept`, zeroed whenever pyramid_ is allocated
  uint32_t count_ = 0, width_ = 0, height_ = 0;
};

}  // namespace penumbra
