// Mip-chain layout shared by the pyramid kernels and their host wrapper: each level halves the previous
// one (floor, at least 1) down to 1x1; levels are stored one after another in one buffer. A PyramidBatch
// describes one dispatch of the batched schedule (several levels per launch, host/stages/pyramid.h).
#ifndef PENUMBRA_KERNELS_SHARED_PYRAMID_H
#define PENUMBRA_KERNELS_SHARED_PYRAMID_H

#include "kernels/shared/common.h"
#include "kernels/shared/light_view.h"  // pyramid_prefetch_ahead projects a pixel into the map

#define PYRAMID_MAX_LEVELS 16  // 2^15 = the largest supported image side, plus the base level

typedef struct PyramidLevel {
  uint offset;         // first texel of the level in its buffer
  uint width, height;  // texels
  uint pad0;
} PyramidLevel;

// Levels level[0..count) computed by one dispatch from `src`. Work-group (gx, gy) owns the tile
// [gx tile, (gx+1) tile) x [gy tile, (gy+1) tile) of the last level and, at level j, that tile scaled by
// 2^(count-1-j); the last group along an axis owns everything up to the edge. A group that is not the
// last along x computes haloX[j] texels past its owned span at level j: the texels the 3-tap footprints of
// odd sizes make the later levels of its tile read (haloX[count-1] = 0; haloX[j] = 2 haloX[j+1] + the
// width of level j is odd). The first min-max pass reads the depth map and also writes `src` (level 0).
typedef struct PyramidBatch {
  PyramidLevel src;                        // input level (offset into the input buffer; min-max: also output)
  PyramidLevel level[PYRAMID_MAX_LEVELS];  // output levels (offsets into the output buffer)
  uint haloX[PYRAMID_MAX_LEVELS], haloY[PYRAMID_MAX_LEVELS];
  uint count;  // output levels, 1..PYRAMID_MAX_LEVELS - 1
  uint tile;   // edge of a work-group's tile of level[count-1], texels
  uint pad0, pad1;
} PyramidBatch;

#if PENUMBRA_HOST
static_assert(sizeof(PyramidLevel) == 16, "PyramidLevel layout is shared with OpenCL C");
static_assert(sizeof(PyramidBatch) == 16 + 16 * PYRAMID_MAX_LEVELS + 8 * PYRAMID_MAX_LEVELS + 16,
              "PyramidBatch layout is shared with OpenCL C");
static_assert(offsetof(PyramidBatch, count) == 16 + 24 * PYRAMID_MAX_LEVELS, "PyramidBatch layout");
#else

// Taps of destination texel `x` along one axis when a source of `src` texels shrinks to `dst`: an exact
// area average (the footprint [x src/dst, (x+1) src/dst] covers 1, 2 or 3 texels; odd sizes weight the
// outer two by their coverage, as in NVIDIA's non-power-of-two mipmapping note). Returns the tap count.
inline int pyramid_taps(uint x, uint src, uint dst, int* first, float* w) {
  *first = 2 * x;
  if (src == 1) {
    *first = 0, w[0] = 1.0f;
    return 1;
  }
  if (src % 2 == 0) {
    w[0] = w[1] = 0.5f;
    return 2;
  }
  const float norm = 1.0f / (float)(2 * dst + 1);
  w[0] = (float)(dst - x) * norm, w[1] = (float)dst * norm, w[2] = (float)(x + 1) * norm;
  return 3;
}

// The footprint of destination texel (x, y) of level `d` in level `s`: nx x ny taps from (x0, y0).
typedef struct PyramidTaps {
  int x0, y0, nx, ny;
  float wx[3], wy[3];
} PyramidTaps;

inline PyramidTaps pyramid_footprint(uint x, uint y, PyramidLevel s, PyramidLevel d) {
  PyramidTaps t;
  t.nx = pyramid_taps(x, s.width, d.width, &t.x0, t.wx);
  t.ny = pyramid_taps(y, s.height, d.height, &t.y0, t.wy);
  return t;
}

// Texels of level `level` (texels across) covering base interval [a, b] (of `base` texels) along one axis: level
// texel x covers at least the base interval [x W0/Wl, (x+1) W0/Wl] (pyramid_taps footprints are conservative),
// widened by 1e-3 level texels against rounding.
inline int2 pyramid_cover_span(float a, float b, uint base, uint level) {
  const float s = (float)level / (float)base;
  return (int2)(max((int)pn_floor(a * s - 1e-3f), 0), min((int)pn_floor(b * s + 1e-3f), (int)level - 1));
}

// Level 0 of a levels-only min-max pyramid (host/stages/pyramid.h computeMinMaxLevels): the depth map itself, a texel
// read as (z, z), background and NaN as the farthest depth (+inf, +inf): a maximum sees them (nothing there occludes),
// a minimum does not. A select, not ?: on vectors (kernels/pyramid.cl pyramid_depth_range says why).
inline float2 pyramid_far_range(float z) { return select((float2)(INFINITY), (float2)(z), (int2)(-isfinite(z))); }

// Texels across and down level l of a levels-only min-max pyramid over a width x height map (0: the map itself).
inline uint2 pyramid_level_size(__constant const PyramidLevel* levels, uint l, uint width, uint height) {
  return l == 0 ? (uint2)(width, height) : (uint2)(levels[l - 1].width, levels[l - 1].height);
}

// The finest level of a levels-only min-max pyramid over a width x height map (0: the map itself; l >= 1: levels[l -
// 1], of `levelCount`) whose texels covering [a, b] (inside the map) span at most most + 1 a side, or the coarsest
// level; those texels' spans in *sx and *sy (pyramid_cover_span).
inline uint pyramid_cover_level(__constant const PyramidLevel* levels, uint levelCount, uint width, uint height,
                                float2 a, float2 b, int most, int2* sx, int2* sy) {
  // Levels on which the box spans most + 4 texels or more along an axis fail the test below for certain (the spans'
  // floors and clamps take off less than 3 texels, and rounding far less than 1), and so do the finer ones: the search
  // starts past them, with a product per level instead of the spans' divisions and floors.
  const float2 extent = b - a, limit = (float)(most + 4) * (float2)((float)width, (float)height);
  uint l = 0;
  while (l < levelCount && any(extent * convert_float2(pyramid_level_size(levels, l, width, height)) >= limit)) ++l;
  for (;; ++l) {
    const uint2 size = pyramid_level_size(levels, l, width, height);
    *sx = pyramid_cover_span(a.x, b.x, width, size.x), *sy = pyramid_cover_span(a.y, b.y, height, size.y);
    if (!(sx->y - sx->x > most || sy->y - sy->x > most) || l == levelCount) return l;
  }
}

#define PYRAMID_PREFETCH_LEVELS 4  // pyramid levels 1.. whose node under a point pyramid_prefetch_ahead asks for

// Asks the caches (CPU devices, PN_PREFETCH) for what the narrowest pyramid_depth_range_of queries of G-buffer pixel
// `ahead` will read: where its position projects into the width x height map `base`, the texel and the one above it,
// and the nodes over it in the first PYRAMID_PREFETCH_LEVELS of the `levelCount` levels; nothing for background or a
// point off the map. Those reads come from memory (a 4096^2 map is 64 MiB, and neighbouring pixels' texels lie rows
// apart). Shading kernels call it for the pixel PN_PREFETCH_AHEAD work-items on: pcss's shading on
// scenes/default.json at 640x360, 33.2 -> 32.0 ms (docs/performance.md, "Prefetching"). No-op off CPU devices.
inline void pyramid_prefetch_ahead(__global const float4* position, __constant const LightViewGpu* lv,
                                   __global const float* base, __global const float2* pyramid,
                                   __constant const PyramidLevel* levels, uint levelCount, uint ahead, uint count) {
#if PN_PREFETCHES
  int2 texel;
  if (!lv_pixel_texel(position, lv, ahead, count, &texel)) return;
  const uint width = (uint)lv->width, height = (uint)lv->height, x = (uint)texel.x, y = (uint)texel.y;
  PN_PREFETCH(&base[(size_t)y * width + x]);
  if (y + 1 < height) PN_PREFETCH(&base[(size_t)(y + 1) * width + x]);
  for (uint l = 0; l < min(levelCount, (uint)PYRAMID_PREFETCH_LEVELS); ++l) {
    const PyramidLevel level = levels[l];
    PN_PREFETCH(&pyramid[level.offset + (size_t)min(y >> (l + 1), level.height - 1) * level.width +
                         min(x >> (l + 1), level.width - 1)]);
  }
#endif
}

// (min, max) of depth over every base texel the box [lo, hi] (texels) touches, from a width x height depth map `base`
// and the `levelCount` levels 1.. of its min-max pyramid (levels[0] is level 1): the finest level where the box covers
// at most 2 x 2 texels, the depth map itself (pyramid_far_range) where that is level 0. A box reaching outside the
// map also gets `outside` (the value of texels beyond it); an empty box inside it, (+inf, -inf).
inline float2 pyramid_depth_range_of(__global const float* base, __global const float2* pyramid,
                                     __constant const PyramidLevel* levels, uint levelCount, uint width, uint height,
                                     float2 lo, float2 hi, float outside) {
  const float2 size = (float2)((float)width, (float)height);
  float2 range = (float2)(INFINITY, -INFINITY);
  if (any(lo < (float2)(0.0f)) || any(hi > size)) range = (float2)(outside);
  const float2 a = clamp(lo, (float2)(0.0f), size), b = clamp(hi, a, size);
  if (!(b.x > a.x && b.y > a.y)) return range;
  int2 sx, sy;
  const uint l = pyramid_cover_level(levels, levelCount, width, height, a, b, 1, &sx, &sy);
  if (l == 0) {
    for (int y = sy.x; y <= sy.y; ++y)
      for (int x = sx.x; x <= sx.y; ++x) {
        const float2 v = pyramid_far_range(base[(size_t)y * width + x]);
        range = (float2)(fmin(range.x, v.x), fmax(range.y, v.y));
      }
    return range;
  }
  const PyramidLevel level = levels[l - 1];
  for (int y = sy.x; y <= sy.y; ++y)
    for (int x = sx.x; x <= sx.y; ++x) {
      const float2 v = pyramid[level.offset + (size_t)y * level.width + x];
      range = (float2)(fmin(range.x, v.x), fmax(range.y, v.y));
    }
  return range;
}

// The farthest depth over every base texel that meets the disk of radius `radius` (texels) around `centre`, from the
// same map and pyramid as pyramid_depth_range_of, at the finest level where the disk's square spans at most 4 x 4
// texels, less those whose nominal square (pyramid_cover_span's [x W0/Wl, (x+1) W0/Wl] a side) lies wholly outside
// the disk: a base texel meeting the disk lies inside the footprint of every level texel whose nominal square it meets
// (pyramid_taps footprints hold their nominal interval and every texel it touches), so one of the texels kept holds
// it. `outside` where the square reaches beyond the map; -inf for an empty disk. Tighter than the square's range: a
// coarse level's 2 x 2 texels can hold twice the square a side, and the square's corners lie outside the disk.
inline float pyramid_far_in_disk(__global const float* base, __global const float2* pyramid,
                                 __constant const PyramidLevel* levels, uint levelCount, uint width, uint height,
                                 float2 centre, float radius, float outside) {
  const float2 size = (float2)((float)width, (float)height), lo = centre - radius, hi = centre + radius;
  if (any(lo < (float2)(0.0f)) || any(hi > size)) return outside;
  if (!(hi.x > lo.x && hi.y > lo.y)) return -INFINITY;
  int2 sx, sy;
  const uint l = pyramid_cover_level(levels, levelCount, width, height, lo, hi, 3, &sx, &sy);
  const uint2 levelSize = pyramid_level_size(levels, l, width, height);
  const float2 step = size / convert_float2(levelSize);  // base texels per level texel, a side
  const float reach2 = (radius + 1e-3f) * (radius + 1e-3f);
  float far = -INFINITY;
  for (int y = sy.x; y <= sy.y; ++y)
    for (int x = sx.x; x <= sx.y; ++x) {
      const float2 a = (float2)((float)x, (float)y) * step, d = clamp(centre, a, a + step) - centre;
      if (dot(d, d) > reach2) continue;  // its nominal square lies outside the disk
      far = fmax(far, l == 0 ? pyramid_far_range(base[(size_t)y * width + x]).y
                             : pyramid[levels[l - 1].offset + (size_t)y * levels[l - 1].width + x].y);
    }
  return far;
}
#endif

#endif
