// Summed-area tables (Crow 1984) shared by the SAT stage and the kernels that filter with them: tiling
// constants, the table descriptor, per-mode storage types and the 4-corner box lookup with bilinear
// weights (the exact integral of the piecewise-constant image over a continuous box; Hensley et al. 2005,
// sec. 4). Kernels select the storage by -DSAT_MODE=SAT_MODE_* and -DSAT_CHANNELS=1|2|4 before including.
#ifndef PENUMBRA_KERNELS_SHARED_SAT_H
#define PENUMBRA_KERNELS_SHARED_SAT_H

#include "kernels/shared/common.h"

#define SAT_TILE 32           // texels per tile side in the tiled scan (work-group x size)
#define SAT_GROUP_Y 8         // work-group y size of the tile kernels: each work-item covers SAT_TILE / 8 rows
#define SAT_CARRY_GROUP 64    // work-group size of sat_carry
#define SAT_REDUCE_GROUP 256  // work-group size of the mean reduction
#define SAT_LINE_BLOCK 32     // columns per work-item in sat_lines_columns (best of 16/32/64 on PoCL)

// Storage modes. Fixed-point tables hold round(x * 2^fractionBits) summed modulo 2^32 or 2^64: the
// table itself wraps, but every box sum (a difference of corners) is exact while it fits the signed range.
#define SAT_MODE_FP32 0     // float, data offset by `offset` (the mean) before summing
#define SAT_MODE_FIXED32 1  // uint, modular
#define SAT_MODE_FIXED64 2  // ulong, modular
#define SAT_MODE_FP64 3     // double (devices with PENUMBRA_HAS_FP64)

// What a lookup needs to read a table (passed by value).
typedef struct SatTableDesc {
  uint width, height;   // texels of the source image (the table has the same size)
  uint channels;        // 1, 2 or 4 interleaved
  uint mode;            // SAT_MODE_*
  float scale;          // fixed point: 2^fractionBits (1 otherwise)
  float invScale;       // 1 / scale
  uint tilesX, tilesY;  // tiled scan only: ceil(size / SAT_TILE)
} SatTableDesc;

#if PENUMBRA_HOST
static_assert(sizeof(SatTableDesc) == 32, "SatTableDesc layout is shared with OpenCL C");
static_assert(offsetof(SatTableDesc, scale) == 16 && offsetof(SatTableDesc, tilesY) == 28);
#else

#ifndef SAT_MODE
#define SAT_MODE SAT_MODE_FP32
#endif
#ifndef SAT_CHANNELS
#define SAT_CHANNELS 1
#endif

#define SAT_F PN_VEC(float, SAT_CHANNELS)  // a texel of the source image
#if SAT_MODE == SAT_MODE_FP32
#define SAT_T SAT_F
#define SAT_LOAD(x, offset, scale) ((x) - (offset))
#define SAT_TO_FLOAT(s, invScale) (s)
#elif SAT_MODE == SAT_MODE_FIXED32
#define SAT_T PN_VEC(uint, SAT_CHANNELS)
#define SAT_LOAD(x, offset, scale) PN_CAT(as_, SAT_T)(PN_CAT(PN_CONVERT(int, SAT_CHANNELS), _sat_rte)((x) * (scale)))
#define SAT_TO_FLOAT(s, invScale) \
  (PN_CONVERT(float, SAT_CHANNELS)(PN_CAT(as_, PN_VEC(int, SAT_CHANNELS))(s)) * (invScale))
#elif SAT_MODE == SAT_MODE_FIXED64
#define SAT_T PN_VEC(ulong, SAT_CHANNELS)
#define SAT_LOAD(x, offset, scale) PN_CAT(as_, SAT_T)(PN_CAT(PN_CONVERT(long, SAT_CHANNELS), _sat_rte)((x) * (scale)))
#define SAT_TO_FLOAT(s, invScale) \
  (PN_CONVERT(float, SAT_CHANNELS)(PN_CAT(as_, PN_VEC(long, SAT_CHANNELS))(s)) * (invScale))
#elif SAT_MODE == SAT_MODE_FP64
#ifndef PENUMBRA_HAS_FP64
#error "SAT_MODE_FP64 needs a device with fp64 (PENUMBRA_HAS_FP64)"
#endif
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#define SAT_T PN_VEC(double, SAT_CHANNELS)
#define SAT_LOAD(x, offset, scale) PN_CONVERT(double, SAT_CHANNELS)(x)
#define SAT_TO_FLOAT(s, invScale) PN_CONVERT(float, SAT_CHANNELS)(s)
#else
#error "unknown SAT_MODE"
#endif

// The offset of an fp32 table as a texel (the first SAT_CHANNELS of a float4).
inline SAT_F sat_offset(__global const float* offset) {
#if SAT_CHANNELS == 1
  return offset[0];
#elif SAT_CHANNELS == 2
  return (float2)(offset[0], offset[1]);
#else
  return vload4(0, offset);
#endif
}

// I(i, j): the sum of texels with x < i and y < j (0 on the first row and column of the padded table).
inline SAT_T sat_corner(__global const SAT_T* sat, SatTableDesc t, int i, int j) {
  return (i <= 0 || j <= 0) ? (SAT_T)0 : sat[(size_t)(j - 1) * t.width + (i - 1)];
}

// Sum of the image over the continuous box [lo, hi] (texel units; texel (x, y) covers [x, x+1] x [y, y+1]),
// clamped to the image. I(u, v) is bilinear between integer corners: the sum is sum_a sum_b sx[a] sy[b] I(x_a, y_b)
// over the 4 x 4 corners around lo and hi, with sx = (-wx0, -wx1, wx2, wx3) (and sy) the bilinear weights, negative at
// the low side. Each of sx and sy sums to 0, so every corner may first have the first row's and the first column's
// values taken from it: the 9 integer box sums from corner (0, 0) to (a, b), a, b >= 1, formed before weighting, keep
// fixed-point modes exact until their conversion and are box-sized (no prefix sum of the whole image is converted).
// The same sum as the 16 two-corner differences of every low and high corner pair, with 9 conversions instead of 16.
inline SAT_F sat_box_sum(__global const SAT_T* sat, SatTableDesc t, __global const float* offset, float2 lo,
                         float2 hi) {
  const float2 size = (float2)((float)t.width, (float)t.height);
  lo = clamp(lo, (float2)(0.0f), size);
  hi = clamp(hi, lo, size);
  const int2 c0 = min(convert_int2(pn_floor2(lo)), (int2)(t.width - 1, t.height - 1));
  const int2 c1 = min(convert_int2(pn_floor2(hi)), (int2)(t.width - 1, t.height - 1));
  const float2 f0 = lo - convert_float2(c0), f1 = hi - convert_float2(c1);
  const int xs[4] = {c0.x, c0.x + 1, c1.x, c1.x + 1}, ys[4] = {c0.y, c0.y + 1, c1.y, c1.y + 1};
  const float wx[4] = {1.0f - f0.x, f0.x, 1.0f - f1.x, f1.x}, wy[4] = {1.0f - f0.y, f0.y, 1.0f - f1.y, f1.y};
  const float sx[4] = {-wx[0], -wx[1], wx[2], wx[3]}, sy[4] = {-wy[0], -wy[1], wy[2], wy[3]};
  SAT_T row[4][3];  // each corner less its row's first
  for (int b = 0; b < 4; ++b) {
    const SAT_T first = sat_corner(sat, t, xs[0], ys[b]);
    for (int a = 1; a < 4; ++a) row[b][a - 1] = sat_corner(sat, t, xs[a], ys[b]) - first;
  }
  SAT_F sum = 0.0f;
  for (int b = 1; b < 4; ++b)
    for (int a = 1; a < 4; ++a) {
      const SAT_T box = row[b][a - 1] - row[0][a - 1];  // the box from corner (0, 0) to (a, b)
      sum += (sx[a] * sy[b]) * SAT_TO_FLOAT(box, t.invScale);
    }
#if SAT_MODE == SAT_MODE_FP32
  sum += sat_offset(offset) * ((hi.x - lo.x) * (hi.y - lo.y));
#endif
  return sum;
}

// Mean over the box (0 for an empty box, e.g. entirely outside the image).
inline SAT_F sat_box_mean(__global const SAT_T* sat, SatTableDesc t, __global const float* offset, float2 lo,
                          float2 hi) {
  const SAT_F sum = sat_box_sum(sat, t, offset, lo, hi);
  const float2 a = clamp(lo, (float2)(0.0f), (float2)((float)t.width, (float)t.height));
  const float2 b = clamp(hi, a, (float2)((float)t.width, (float)t.height));
  const float area = (b.x - a.x) * (b.y - a.y);
  return area > 0.0f ? sum / area : (SAT_F)0.0f;
}

#endif
#endif
