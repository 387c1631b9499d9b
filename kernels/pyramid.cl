// Pyramids: mip chains of moments (exact area averages, odd sizes included, so every level keeps the
// mean) and the min-max depth pyramid of a hierarchical shadow map (VSSM, Yang et al. 2010, sec. 4):
// conservative min/max over every texel a footprint touches. *_batch: several levels per dispatch, a
// work-group per tile of the last one, through local memory, recomputing the halo that odd sizes' 3-tap
// footprints need (design: host/stages/pyramid.h); the per-level kernels are the reference schedule.
// Options: PYRAMID_CHANNELS (1, 2, 4 moments) and STORE_HALF (moments stored as half, averaged in fp32:
// kernels/shared/storage.h), or PYRAMID_MINMAX with PYRAMID_FROM_DEPTH for the first pass.
#include "kernels/shared/moments.h"  // ESM's log-space taps
#include "kernels/shared/pyramid.h"
#include "kernels/shared/storage.h"

#ifndef PYRAMID_CHANNELS
#define PYRAMID_CHANNELS 1
#endif
#ifndef PYRAMID_MINMAX
#define PYRAMID_MINMAX 0
#endif
#ifndef PYRAMID_FROM_DEPTH
// Min-max, the first pass: 1 reads the depth map and also writes level 0 (background and NaN the empty range);
// 2 reads it for levels 1.. only, which lookups read beside the map itself (background and NaN the farthest depth,
// kernels/shared/pyramid.h pyramid_far_range and pyramid_depth_range_of).
#define PYRAMID_FROM_DEPTH 0
#endif

#if PYRAMID_MINMAX
typedef float2 PyramidTexel;  // (min, max) light depth
#define PyramidStored float2
#define PYRAMID_STORE(p, i, v) ((p)[i] = (v))
#define PYRAMID_ROUND(v) (v)
#define PYRAMID_STRIDE 1
#else
typedef PN_VEC(float, PYRAMID_CHANNELS) PyramidTexel;  // moments, as computed
#define PyramidStored PN_STORED(PYRAMID_CHANNELS)     // moments, as stored (float vectors or half)
#define PYRAMID_STORE(p, i, v) PN_STORE(PYRAMID_CHANNELS, p, i, v)
#define PYRAMID_ROUND(v) PN_ROUND(PYRAMID_CHANNELS, v)  // levels kept for the next one are read back as stored
#define PYRAMID_STRIDE PN_STRIDE(PYRAMID_CHANNELS)      // stored elements per texel (half: one per channel)
#endif
#if PYRAMID_FROM_DEPTH
#define PyramidInput float
#else
#define PyramidInput PyramidStored
#endif

// Level 0 of the min-max pyramid: (d, d) for a drawn texel, the empty interval (+INF, -INF) for background
// and NaN, so they never widen a range. A select, not ?: on vectors: PoCL turns the latter into AVX-512
// masked loads that run ~100x slower on the EPYC test machines (750 ms instead of 9 ms at 2048^2).
inline float2 pyramid_depth_range(float z) {
  return select((float2)(INFINITY, -INFINITY), (float2)(z, z), (int2)(-isfinite(z)));
}

// Texel i of a level in global memory (PYRAMID_LOAD) or local memory (PYRAMID_LOAD_LOCAL), as computed.
#if PYRAMID_FROM_DEPTH == 1
#define PYRAMID_LOAD(p, i) pyramid_depth_range((p)[i])
#elif PYRAMID_FROM_DEPTH == 2
#define PYRAMID_LOAD(p, i) pyramid_far_range((p)[i])
#elif PYRAMID_MINMAX
#define PYRAMID_LOAD(p, i) ((p)[i])
#else
#define PYRAMID_LOAD(p, i) PN_LOAD(PYRAMID_CHANNELS, p, i)
#endif
#define PYRAMID_LOAD_LOCAL(p, i) ((p)[i])

// One destination texel from its taps `t` in `src` (row pitch `pitch`), the same code for global and local
// sources. Means: sum over rows of (sum over columns of w * texel), the one order both schedules use, so
// they agree bit for bit. Min-max is exact in any order.
#if PYRAMID_MINMAX
#define PYRAMID_REDUCE(src, pitch, t, LOAD)                              \
  float2 range = (float2)(INFINITY, -INFINITY);                          \
  for (int j = 0; j < t.ny; ++j)                                         \
    for (int i = 0; i < t.nx; ++i) {                                     \
      const float2 v = LOAD(src, (size_t)(t.y0 + j) * pitch + t.x0 + i); \
      range = (float2)(fmin(range.x, v.x), fmax(range.y, v.y));          \
    }                                                                    \
  return range;
#else
#define PYRAMID_REDUCE(src, pitch, t, LOAD)                                                           \
  PyramidTexel sum = 0.0f;                                                                            \
  for (int j = 0; j < t.ny; ++j) {                                                                    \
    PyramidTexel row = 0.0f;                                                                          \
    for (int i = 0; i < t.nx; ++i) row += t.wx[i] * LOAD(src, (size_t)(t.y0 + j) * pitch + t.x0 + i); \
    sum += t.wy[j] * row;                                                                             \
  }                                                                                                   \
  return sum;
#endif

inline PyramidTexel pyramid_reduce_global(__global const PyramidInput* src, uint pitch, PyramidTaps t) {
  PYRAMID_REDUCE(src, pitch, t, PYRAMID_LOAD)
}

inline PyramidTexel pyramid_reduce_local(__local const PyramidTexel* src, uint pitch, PyramidTaps t) {
  PYRAMID_REDUCE(src, pitch, t, PYRAMID_LOAD_LOCAL)
}

#if PYRAMID_FROM_DEPTH == 2
// Levels-only min-max from the depth map, with `tilesX` > 0: the texels of the map's 8 x 8 tiles (tx, ty) whose
// tiles[ty * tilesX + tx] is nonzero count as background (host/stages/pyramid.h computeMinMaxLevels: the rasterizer's
// empty tiles, or the tiles no caster reaches).
#define PYRAMID_TILE_LOG2 3
inline bool pyramid_tile_background(__global const uint* tiles, uint tilesX, uint x, uint y) {
  return tilesX != 0u && tiles[(size_t)(y >> PYRAMID_TILE_LOG2) * tilesX + (x >> PYRAMID_TILE_LOG2)] != 0u;
}

inline float2 pyramid_reduce_depth(__global const float* src, uint pitch, PyramidTaps t, __global const uint* tiles,
                                   uint tilesX) {
  float2 range = (float2)(INFINITY, -INFINITY);
  for (int j = 0; j < t.ny; ++j)
    for (int i = 0; i < t.nx; ++i) {
      const uint x = (uint)(t.x0 + i), y = (uint)(t.y0 + j);
      const float z = pyramid_tile_background(tiles, tilesX, x, y) ? INFINITY : src[(size_t)y * pitch + x];
      const float2 v = pyramid_far_range(z);
      range = (float2)(fmin(range.x, v.x), fmax(range.y, v.y));
    }
  return range;
}
#define PYRAMID_TILE_PARAMS , __global const uint *tiles, uint tilesX
#else
#define PYRAMID_TILE_PARAMS
#endif

// Reference schedule: one level per launch, one work-item per destination texel.
inline void pyramid_level(__global const PyramidInput* src, PyramidLevel s, __global PyramidStored* dst,
                          PyramidLevel d) {
  const uint x = get_global_id(0), y = get_global_id(1);
  if (x >= d.width || y >= d.height) return;
  const PyramidTaps t = pyramid_footprint(x, y, s, d);
  PYRAMID_STORE(dst, d.offset + (size_t)y * d.width + x,
                pyramid_reduce_global(src + (size_t)s.offset * PYRAMID_STRIDE, s.width, t));
}

#if PYRAMID_FROM_DEPTH == 1
// Level 0 (the converted depth map; it starts both buffers) under owned level-1 texel (x, y): its 2x2
// block, to the edge for the last row and column (odd sizes, 1-texel sides). The blocks tile level 0, and
// the footprint has just read them.
inline void pyramid_write_base(__global const float* depth, __global float2* dst, PyramidLevel s, PyramidLevel d,
                               uint x, uint y) {
  const uint x1 = x + 1 == d.width ? s.width : 2 * x + 2, y1 = y + 1 == d.height ? s.height : 2 * y + 2;
  for (uint v = 2 * y; v < y1; ++v)
    for (uint u = 2 * x; u < x1; ++u)
      dst[s.offset + (size_t)v * s.width + u] = pyramid_depth_range(depth[(size_t)v * s.width + u]);
}
#endif

// A work-group's span along one axis at a level: it writes [lo, own) and computes [lo, end).
typedef struct PyramidSpan {
  uint lo, own, end;
} PyramidSpan;

inline PyramidSpan pyramid_span(uint group, uint groups, uint tile, uint shift, uint size, uint halo) {
  const bool last = group + 1 == groups;
  PyramidSpan s;
  s.lo = (group * tile) << shift;
  s.own = last ? size : ((group + 1) * tile) << shift;
  s.end = last ? size : s.own + halo;
  return s;
}

// Batched schedule: b.count levels per dispatch (layout and ownership: PyramidBatch). Level j of the group's
// spans is kept in local memory (`even` or `odd` by the parity of j) for level j + 1; the first level reads
// the input in global memory. Every barrier is reached by the whole group (the level loop is uniform).
inline void pyramid_batch(__global const PyramidInput* src, __global PyramidStored* dst, const PyramidBatch b,
                          __local PyramidTexel* even, __local PyramidTexel* odd PYRAMID_TILE_PARAMS) {
  const uint gx = get_group_id(0), gy = get_group_id(1), ngx = get_num_groups(0), ngy = get_num_groups(1);
  PyramidSpan px = {0, 0, 0}, py = {0, 0, 0};  // the previous level's spans (its origin and pitch in local memory)
  for (uint j = 0; j < b.count; ++j) {
    const PyramidLevel s = j == 0 ? b.src : b.level[j - 1], d = b.level[j];
    const uint shift = b.count - 1 - j;
    const PyramidSpan sx = pyramid_span(gx, ngx, b.tile, shift, d.width, b.haloX[j]);
    const PyramidSpan sy = pyramid_span(gy, ngy, b.tile, shift, d.height, b.haloY[j]);
    __local PyramidTexel* out = (j & 1) ? odd : even;
    __local const PyramidTexel* in = (j & 1) ? even : odd;
    for (uint y = sy.lo + get_local_id(1); y < sy.end; y += get_local_size(1))
      for (uint x = sx.lo + get_local_id(0); x < sx.end; x += get_local_size(0)) {
        PyramidTaps t = pyramid_footprint(x, y, s, d);
        PyramidTexel v;
        if (j == 0) {
#if PYRAMID_FROM_DEPTH == 2
          v = pyramid_reduce_depth(src, s.width, t, tiles, tilesX);  // level 0: the map itself, offset 0
#else
          v = pyramid_reduce_global(src + (size_t)s.offset * PYRAMID_STRIDE, s.width, t);
#endif
        } else {
          t.x0 -= px.lo, t.y0 -= py.lo;
          v = pyramid_reduce_local(in, px.end - px.lo, t);
        }
        if (j + 1 < b.count) out[(y - sy.lo) * (sx.end - sx.lo) + x - sx.lo] = PYRAMID_ROUND(v);
        if (x < sx.own && y < sy.own) {
          PYRAMID_STORE(dst, d.offset + (size_t)y * d.width + x, v);
#if PYRAMID_FROM_DEPTH == 1
          if (j == 0) pyramid_write_base(src, dst, s, d, x, y);
#endif
        }
      }
    barrier(CLK_LOCAL_MEM_FENCE);
    px = sx, py = sy;
  }
}

#if PYRAMID_MINMAX && PYRAMID_FROM_DEPTH != 1
// The rows schedule of the levels-only min-max pyramid (CPU devices; host/stages/pyramid.h PyramidSchedule::Rows):
// one level per launch, a work-item per PYRAMID_ROW_TEXELS destination texels of a row, its footprint's source rows
// read as explicit vectors (PoCL vectorizes neither the batched kernel's per-texel footprint loops nor across
// work-items that loop). Min-max is exact in any order: the result equals the batched schedule's bit for bit.
#define PYRAMID_ROW_TEXELS 8

// (min, max) of the 8 destination texels of one source row whose footprints start at `row` (2 source texels each,
// and a third, the next pair's first, where the source width is odd). From the depth map, `kept` (lanes -1 or 0) and
// `keptNext` (the third texel) say which of the 16 + 1 texels are not taken as background (pyramid_row_kept); the
// levels' variant ignores them (the first level already took them).
#if PYRAMID_FROM_DEPTH == 2
// `kept` of a 16-texel row starting at texel (x, y), x on a tile's first column: its two tiles' lanes.
inline int16 pyramid_row_kept(__global const uint* tiles, uint tilesX, uint x, uint y) {
  const int a = pyramid_tile_background(tiles, tilesX, x, y) ? 0 : -1;
  const int b = pyramid_tile_background(tiles, tilesX, x + 8u, y) ? 0 : -1;
  return (int16)((int8)(a), (int8)(b));
}

inline void pyramid_row_range(__global const float* row, int odd, int16 kept, int keptNext, float8* lo, float8* hi) {
  const float16 a = vload16(0, row);
  const float16 v = select((float16)(INFINITY), a, isfinite(a) & kept);  // pyramid_far_range: background the farthest
  float8 mn = fmin(v.even, v.odd), mx = fmax(v.even, v.odd);
  if (odd) {
    const float next = keptNext ? pyramid_far_range(row[16]).x : INFINITY;
    const float8 e = v.even, third = (float8)(e.s1234, e.s567, next);
    mn = fmin(mn, third), mx = fmax(mx, third);
  }
  *lo = fmin(*lo, mn), *hi = fmax(*hi, mx);
}
#else
inline void pyramid_row_range(__global const float2* row, int odd, int16 kept, int keptNext, float8* lo, float8* hi) {
  const float16 a = vload16(0, (__global const float*)row), b = vload16(1, (__global const float*)row);
  const float16 mins = (float16)(a.even, b.even), maxs = (float16)(a.odd, b.odd);  // of the 16 source texels
  float8 mn = fmin(mins.even, mins.odd), mx = fmax(maxs.even, maxs.odd);
  if (odd) {
    const float2 next = row[16];
    const float8 lo3 = mins.even, hi3 = maxs.even;
    mn = fmin(mn, (float8)(lo3.s1234, lo3.s567, next.x)), mx = fmax(mx, (float8)(hi3.s1234, hi3.s567, next.y));
  }
  *lo = fmin(*lo, mn), *hi = fmax(*hi, mx);
}
#endif

// From the depth map, tiles and tilesX as pyramid_reduce_depth's; levels ignore them.
__kernel void pyramid_minmax_rows(__global const PyramidInput* src, PyramidLevel s, __global float2* dst,
                                  PyramidLevel d, __global const uint* tiles, uint tilesX) {
  const uint x0 = get_global_id(0) * PYRAMID_ROW_TEXELS, y = get_global_id(1);
  if (x0 >= d.width || y >= d.height) return;
  src += s.offset;
  __global float2* out = dst + d.offset + (size_t)y * d.width;
  int firstRow;
  float w[3];
  const int rows = pyramid_taps(y, s.height, d.height, &firstRow, w);
  if (s.width > 1 && x0 + PYRAMID_ROW_TEXELS <= d.width) {  // the footprints start at 2 x0 and lie in the row
    float8 lo = (float8)(INFINITY), hi = (float8)(-INFINITY);
    for (int j = 0; j < rows; ++j) {
      const uint y = (uint)(firstRow + j);
#if PYRAMID_FROM_DEPTH == 2
      const int16 kept = pyramid_row_kept(tiles, tilesX, 2 * x0, y);
      const int keptNext = (s.width & 1) && !pyramid_tile_background(tiles, tilesX, 2 * x0 + 16u, y);
#else
      const int16 kept = (int16)(-1);
      const int keptNext = 1;
#endif
      pyramid_row_range(src + (size_t)y * s.width + 2 * x0, s.width & 1, kept, keptNext, &lo, &hi);
    }
    float16 both;
    both.even = lo, both.odd = hi;
    vstore16(both, 0, (__global float*)(out + x0));
    return;
  }
  for (uint x = x0; x < min(x0 + PYRAMID_ROW_TEXELS, d.width); ++x)  // the row's last texels; a 1-wide source
#if PYRAMID_FROM_DEPTH == 2
    out[x] = pyramid_reduce_depth(src, s.width, pyramid_footprint(x, y, s, d), tiles, tilesX);
#else
    out[x] = pyramid_reduce_global(src, s.width, pyramid_footprint(x, y, s, d));
#endif
}

// Two levels per launch where both halvings are exact (the source's width a multiple of 32, its height of 4; the host
// checks): a work-item takes 8 texels of the second level `d2`, the 2 x 16 texels of the first `d1` over them and the
// 4 x 32 source texels under those, so the first level is written and not read back (a 4096^2 map's level 1 is 32 MiB).
// The same minima and maxima of the same texels as two pyramid_minmax_rows launches, bit for bit. From the depth map,
// with `tilesX` > 0: backgroundTiles[ty * tilesX + tx] nonzero where the map's 8 x 8 tile (tx, ty) is taken as
// background (pyramid_reduce_depth); a work-item's 32 x 4 texels lie in 4 tiles of one row, and where all four are
// its texels are written as the background's (+inf, +inf) without reading them, else the others' texels read. With
// `keep`: kept[item] (one per work-item, row by row) nonzero where the levels already hold its background from a build
// before (MinMaxLevels, which alone writes them), and then it writes nothing either; each work-item sets its own.
__kernel void pyramid_minmax_rows2(__global const PyramidInput* src, PyramidLevel s, __global float2* dst,
                                   PyramidLevel d1, PyramidLevel d2, __global const uint* backgroundTiles, uint tilesX,
                                   __global uint* kept, int keep) {
  const uint x2 = get_global_id(0) * PYRAMID_ROW_TEXELS, y2 = get_global_id(1);
  if (x2 >= d2.width || y2 >= d2.height) return;
  src += s.offset;
#if PYRAMID_FROM_DEPTH == 2
  const size_t item = (size_t)y2 * (d2.width / PYRAMID_ROW_TEXELS) + x2 / PYRAMID_ROW_TEXELS;
  // Its 4 tiles (the same tile row for its 4 source rows), the texels of those taken as background left out.
  const int16 keptA = pyramid_row_kept(backgroundTiles, tilesX, 4 * x2, 4 * y2);
  const int16 keptB = pyramid_row_kept(backgroundTiles, tilesX, 4 * x2 + 16u, 4 * y2);
  if (!any(keptA | keptB)) {  // all four taken as background
    if (keep && kept[item] != 0u) return;
    const float16 far = (float16)(INFINITY);  // (min, max) pairs of background texels
    for (uint r = 0; r < 2; ++r) {
      __global float* out = (__global float*)(dst + d1.offset + (size_t)(2 * y2 + r) * d1.width + 2 * x2);
      vstore16(far, 0, out);
      vstore16(far, 1, out);
    }
    vstore16(far, 0, (__global float*)(dst + d2.offset + (size_t)y2 * d2.width + x2));
    if (keep) kept[item] = 1u;
    return;
  }
  if (keep) kept[item] = 0u;
#else
  const int16 keptA = (int16)(-1), keptB = keptA;
#endif
  float16 lo2 = (float16)(INFINITY), hi2 = (float16)(-INFINITY);  // the first level's 16 texels, over both its rows
  for (uint r = 0; r < 2; ++r) {
    const uint y1 = 2 * y2 + r;
    float8 loA = (float8)(INFINITY), hiA = (float8)(-INFINITY), loB = loA, hiB = hiA;
    for (uint j = 0; j < 2; ++j) {
      __global const PyramidInput* row = src + (size_t)(2 * y1 + j) * s.width + 4 * x2;
      pyramid_row_range(row, 0, keptA, 0, &loA, &hiA);
      pyramid_row_range(row + 2 * PYRAMID_ROW_TEXELS, 0, keptB, 0, &loB, &hiB);
    }
    __global float* out = (__global float*)(dst + d1.offset + (size_t)y1 * d1.width + 2 * x2);
    float16 both;
    both.even = loA, both.odd = hiA;
    vstore16(both, 0, out);
    both.even = loB, both.odd = hiB;
    vstore16(both, 1, out);
    lo2 = fmin(lo2, (float16)(loA, loB)), hi2 = fmax(hi2, (float16)(hiA, hiB));
  }
  float16 both;
  both.even = fmin(lo2.even, lo2.odd), both.odd = fmax(hi2.even, hi2.odd);
  vstore16(both, 0, (__global float*)(dst + d2.offset + (size_t)y2 * d2.width + x2));
}
#endif

#if PYRAMID_MINMAX && PYRAMID_FROM_DEPTH
#if PYRAMID_FROM_DEPTH == 1
__kernel void pyramid_minmax_base(__global const float* depth, __global float2* out, PyramidLevel d) {
  const uint x = get_global_id(0), y = get_global_id(1);
  if (x >= d.width || y >= d.height) return;
  const size_t i = (size_t)y * d.width + x;
  out[d.offset + i] = pyramid_depth_range(depth[i]);
}
#endif

#if PYRAMID_FROM_DEPTH == 2
__kernel void pyramid_minmax_batch(__global const float* depth, __global float2* dst, PyramidBatch b,
                                   __local float2* even, __local float2* odd, __global const uint* tiles, uint tilesX) {
  pyramid_batch(depth, dst, b, even, odd, tiles, tilesX);
}
#else
__kernel void pyramid_minmax_batch(__global const float* depth, __global float2* dst, PyramidBatch b,
                                   __local float2* even, __local float2* odd) {
  pyramid_batch(depth, dst, b, even, odd);
}
#endif
#elif PYRAMID_MINMAX
__kernel void pyramid_minmax_down(__global const float2* src, PyramidLevel s, __global float2* dst, PyramidLevel d) {
  pyramid_level(src, s, dst, d);
}

__kernel void pyramid_minmax_batch(__global const float2* src, __global float2* dst, PyramidBatch b,
                                   __local float2* even, __local float2* odd) {
  pyramid_batch(src, dst, b, even, odd);
}
#else
__kernel void pyramid_downsample(__global const PyramidStored* src, PyramidLevel s, __global PyramidStored* dst,
                                 PyramidLevel d) {
  pyramid_level(src, s, dst, d);
}

__kernel void pyramid_downsample_batch(__global const PyramidStored* src, __global PyramidStored* dst, PyramidBatch b,
                                       __local PyramidTexel* even, __local PyramidTexel* odd) {
  pyramid_batch(src, dst, b, even, odd);
}

#if PYRAMID_CHANNELS == 1
// ESM's log-space mips (kernels/shared/moments.h, moments_log_mix): the D with e^(c D) = the area average of
// e^(c d) over the same footprint as pyramid_downsample, around its largest tap of weight > 0 (per level; ESM's
// trilinear lookups are an option, not the default).
__kernel void pyramid_downsample_log(__global const PyramidStored* src, PyramidLevel s, __global PyramidStored* dst,
                                     PyramidLevel d, float c) {
  const uint x = get_global_id(0), y = get_global_id(1);
  if (x >= d.width || y >= d.height) return;
  const PyramidTaps t = pyramid_footprint(x, y, s, d);
  src += (size_t)s.offset * PYRAMID_STRIDE;
  float m = -INFINITY;
  for (int j = 0; j < t.ny; ++j)
    for (int i = 0; i < t.nx; ++i)
      if (t.wx[i] > 0.0f && t.wy[j] > 0.0f) m = fmax(m, PYRAMID_LOAD(src, (size_t)(t.y0 + j) * s.width + t.x0 + i));
  float sum = 0.0f, linear = 0.0f;
  for (int j = 0; j < t.ny; ++j) {
    float row = 0.0f, rowLinear = 0.0f;
    for (int i = 0; i < t.nx; ++i) {
      const float v = PYRAMID_LOAD(src, (size_t)(t.y0 + j) * s.width + t.x0 + i);
      row += t.wx[i] * exp(c * (v - m));
      rowLinear += t.wx[i] * v;
    }
    sum += t.wy[j] * row;
    linear += t.wy[j] * rowLinear;
  }
  PYRAMID_STORE(dst, d.offset + (size_t)y * d.width + x, c > MOMENTS_LOG_MIN_EXPONENT ? m + log(sum) / c : linear);
}
#endif
#endif
