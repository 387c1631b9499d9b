// Moment generation from a rasterized light depth map: one kernel per encoding (VSM, ESM, EVSM2, EVSM4, LVSM,
// MSM), one work-item per texel. Warps and the invalid-depth convention live in shared/moments.h;
// outputs are interleaved float2/float4 texels (half with -DSTORE_HALF, kernels/shared/storage.h, except
// LVSM), LVSM as one float2 plane per layer.
#include "kernels/shared/moments.h"
#include "kernels/shared/storage.h"

#define Stored2 PN_STORED(2)  // a 2-channel texel as stored (float2, or half with -DSTORE_HALF)
#define Stored4 PN_STORED(4)

// Depth texel (x, y) of the window the moments are made over (MomentsParams: origin and pitch in the map).
#define MOMENTS_DEPTH(depth, p, x, y) ((depth) + (size_t)((p).originY + (y)) * (p).pitch + (size_t)((p).originX + (x)))

#define MOMENTS_TEXEL(p)                           \
  uint x = get_global_id(0), y = get_global_id(1); \
  if (x >= (p).width || y >= (p).height) return;   \
  uint texel = y * (p).width + x;                  \
  const float source = *MOMENTS_DEPTH(depth, p, x, y)

// VSM (Donnelly & Lauritzen 2006): (d, d^2).
__kernel void moments_vsm(__global const float* depth, __global Stored2* out, MomentsParams p) {
  MOMENTS_TEXEL(p);
  PN_STORE(2, out, texel, moments_encode(source, p, MOMENTS_KIND_VSM).xy);
}

// ESM, one channel: e^(c (d - 1)), or in log space the normalised depth d (moments_encode).
__kernel void moments_esm(__global const float* depth, __global PN_STORED(1) * out, MomentsParams p) {
  MOMENTS_TEXEL(p);
  PN_STORE(1, out, texel, moments_encode(source, p, MOMENTS_KIND_ESM).x);
}

// EVSM2: the positive warp only, (e^(c+ x), e^(2 c+ x)).
__kernel void moments_evsm2(__global const float* depth, __global Stored2* out, MomentsParams p) {
  MOMENTS_TEXEL(p);
  PN_STORE(2, out, texel, moments_encode(source, p, MOMENTS_KIND_EVSM2).xy);
}

// EVSM4: both warps, (pos, pos^2, neg, neg^2).
__kernel void moments_evsm4(__global const float* depth, __global Stored4* out, MomentsParams p) {
  MOMENTS_TEXEL(p);
  PN_STORE(4, out, texel, moments_encode(source, p, MOMENTS_KIND_EVSM4));
}

// LVSM: plane `l` holds (phi_l(d), phi_l(d)^2) for the layer [p_l, q_l] given in normalised depth.
__kernel void moments_lvsm(__global const float* depth, __global float2* out, __constant float2* layers,
                           MomentsParams p) {
  MOMENTS_TEXEL(p);
  float d = moments_normalize(source, p.depthNear, p.depthInvRange);
  uint plane = p.width * p.height;
  for (uint l = 0; l < p.layerCount; ++l) {
    float w = moments_layer_warp(d, layers[l]);
    out[l * plane + texel] = (float2)(w, w * w);
  }
}

// MSM: four power moments through the quantization transform.
__kernel void moments_msm(__global const float* depth, __global Stored4* out, MomentsParams p) {
  MOMENTS_TEXEL(p);
  PN_STORE(4, out, texel, moments_encode(source, p, MOMENTS_KIND_MSM));
}

// Moments of factor x factor blocks (fp32): output texel (x, y) of ceil(width / factor) x ceil(height / factor) is
// the mean of the encoded moments of map texels [x f, x f + f) x [y f, y f + f), those beyond the map counting as
// empty (the far value, as the filters' borders do). The encodings are linear in what they average, so a box over
// whole blocks of this grid has the moments of the same box over the map. p.width, p.height: the window's size (the
// map's, or a window of it: MOMENTS_DEPTH), beyond which texels count as empty.
// moments_block_sum: the sum over block (x, y), texel by texel.
inline float4 moments_block_sum(__global const float* depth, MomentsParams p, int kind, uint factor, uint x, uint y) {
  float4 sum = (float4)(0.0f);
  for (uint j = 0; j < factor; ++j) {
    const uint sy = y * factor + j;
    for (uint i = 0; i < factor; ++i) {
      const uint sx = x * factor + i;
      const float d = sx < p.width && sy < p.height ? *MOMENTS_DEPTH(depth, p, sx, sy) : INFINITY;
      sum += moments_encode(d, p, kind);
    }
  }
  return sum;
}

#define MOMENTS_REDUCED(name, kind, channels, swizzle)                                                              \
  __kernel void name(__global const float* depth, __global PN_VEC(float, channels) * out, MomentsParams p,          \
                     uint factor) {                                                                                \
    const uint x = get_global_id(0), y = get_global_id(1);                                                          \
    const uint outWidth = (p.width + factor - 1u) / factor, outHeight = (p.height + factor - 1u) / factor;          \
    if (x >= outWidth || y >= outHeight) return;                                                                    \
    const float4 sum = moments_block_sum(depth, p, kind, factor, x, y);                                             \
    out[(size_t)y * outWidth + x] = (sum / (float)(factor * factor))swizzle;                                        \
  }

// VSM's (vssm's SAT over blocks), with the blocks inside the map read as float2 / float4 rows: contiguous loads of
// whole blocks, which PoCL runs 2-3x faster than the texel loop (default.json's 4096^2 map in 4 x 4 blocks: 12 ms ->
// 6 ms); the texel loop is kept for blocks that reach past the map and for other factors.
inline float4 moments_vsm_normalize4(float4 d, MomentsParams p) {
  return select((float4)(1.0f), clamp((d - p.depthNear) * p.depthInvRange, 0.0f, 1.0f), isfinite(d));
}

__kernel void moments_vsm_reduced(__global const float* depth, __global float2* out, MomentsParams p, uint factor) {
  const uint x = get_global_id(0), y = get_global_id(1);
  const uint outWidth = (p.width + factor - 1u) / factor, outHeight = (p.height + factor - 1u) / factor;
  if (x >= outWidth || y >= outHeight) return;
  float2 sum = (float2)(0.0f);
  const bool inside = (x + 1u) * factor <= p.width && (y + 1u) * factor <= p.height;
  if (inside && (factor == 2u || factor % 4u == 0u)) {
    for (uint j = 0; j < factor; ++j) {
      __global const float* row = MOMENTS_DEPTH(depth, p, x * factor, y * factor + j);
      if (factor == 2u) {
        const float2 d = vload2(0, row);
        const float2 z = select((float2)(1.0f), clamp((d - p.depthNear) * p.depthInvRange, 0.0f, 1.0f), isfinite(d));
        sum += (float2)(z.x + z.y, dot(z, z));
        continue;
      }
      for (uint i = 0; i < factor; i += 4u) {
        const float4 z = moments_vsm_normalize4(vload4(0, row + i), p);
        sum += (float2)(z.x + z.y + z.z + z.w, dot(z, z));
      }
    }
  } else {
    sum = moments_block_sum(depth, p, MOMENTS_KIND_VSM, factor, x, y).xy;
  }
  out[(size_t)y * outWidth + x] = sum / (float)(factor * factor);
}

// The same for 2 x 2 blocks on CPU devices (host/stages/moments.cpp): a work-item per 8 blocks of a row of blocks, the
// two depth rows under them read as float16s (moments_vsm_reduced's float2 loads leave PoCL scalar code: 4096^2 in
// 2 x 2 blocks, default.json's vssm map at 640x360, 9.0 -> 2.9 ms, the bandwidth floor). The same sums in the same
// order as moments_vsm_reduced's, uncontracted as its dot(): the same moments bit for bit.
__kernel void moments_vsm_reduced2_rows(__global const float* depth, __global float2* out, MomentsParams p) {
#pragma OPENCL FP_CONTRACT OFF
  const uint x0 = get_global_id(0) * 8u, y = get_global_id(1);
  const uint outWidth = (p.width + 1u) / 2u, outHeight = (p.height + 1u) / 2u;
  if (x0 >= outWidth || y >= outHeight) return;
  __global float2* row = out + (size_t)y * outWidth;
  if ((x0 + 8u) * 2u <= p.width && (y + 1u) * 2u <= p.height) {
    float8 mean = (float8)(0.0f), square = (float8)(0.0f);
    for (uint j = 0; j < 2u; ++j) {
      const float16 d = vload16(0, MOMENTS_DEPTH(depth, p, 2u * x0, 2u * y + j));
      const float16 z = select((float16)(1.0f), clamp((d - p.depthNear) * p.depthInvRange, 0.0f, 1.0f), isfinite(d));
      mean += z.even + z.odd, square += z.even * z.even + z.odd * z.odd;
    }
    float16 both;
    both.even = mean / 4.0f, both.odd = square / 4.0f;
    vstore16(both, 0, (__global float*)(row + x0));
    return;
  }
  for (uint x = x0; x < min(x0 + 8u, outWidth); ++x)  // the row's last blocks, and blocks that reach past the map
    row[x] = moments_block_sum(depth, p, MOMENTS_KIND_VSM, 2u, x, y).xy / 4.0f;
}

MOMENTS_REDUCED(moments_esm_reduced, MOMENTS_KIND_ESM, 1, .x)
MOMENTS_REDUCED(moments_evsm2_reduced, MOMENTS_KIND_EVSM2, 2, .xy)
MOMENTS_REDUCED(moments_evsm4_reduced, MOMENTS_KIND_EVSM4, 4, )
MOMENTS_REDUCED(moments_msm_reduced, MOMENTS_KIND_MSM, 4, )

// 16-bit unorm storage of moments in [0, 1] (LVSM layers, Lauritzen & McCool 2008, sec. 5): texel value
// round-to-nearest-even(clamp(x, 0, 1) * 65535); NaN stores 0. Writes out[outOffset + i] for i < count.
__kernel void moments_pack_unorm16(__global const float* in, __global ushort* out, uint count, uint outOffset) {
  uint i = get_global_id(0);
  if (i >= count) return;
  float x = in[i];
  out[outOffset + i] = convert_ushort_rte(isnan(x) ? 0.0f : clamp(x, 0.0f, 1.0f) * 65535.0f);
}

// Half storage of fp32 moments (running-sum blurs, which ping-pong in fp32): out[i] = in[i] rounded to the
// nearest even half; values beyond the half range become +-INFINITY (the EVSM exponent clamp keeps them in).
__kernel void moments_pack_half(__global const float* in, __global half* out, uint count) {
  uint i = get_global_id(0);
  if (i < count) vstore_half_rte(in[i], i, out);
}
