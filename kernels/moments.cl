// Moment generation from a rasterized light depth map: one kernel per encoding (VSM, ESM, EVSM2, EVSM4, LVSM,
// MSM), one work-item per texel. Warps and the invalid-depth convention live in shared/moments.h;
// outputs are interleaved float2/float4 texels (half with -DSTORE_HALF, kernels/shared/storage.h, except
// LVSM), LVSM as one float2 plane per layer.
#include "kernels/shared/moments.h"
#include "kernels/shared/storage.h"

#define Stored2 PN_STORED(2)  // a 2-channel texel as stored (float2, or half with -DSTORE_HALF)
#define Stored4 PN_STORED(4)

#define MOMENTS_TEXEL(p)                           \
  uint x = get_global_id(0), y = get_global_id(1); \
  if (x >= (p).width || y >= (p).height) return;   \
  uint texel = y * (p).width + x

// VSM (Donnelly & Lauritzen 2006): (d, d^2).
__kernel void moments_vsm(__global const float* depth, __global Stored2* out, MomentsParams p) {
  MOMENTS_TEXEL(p);
  PN_STORE(2, out, texel, moments_encode(depth[texel], p, MOMENTS_KIND_VSM).xy);
}

// ESM, one channel: e^(c (d - 1)), or in log space the normalised depth d (moments_encode).
__kernel void moments_esm(__global const float* depth, __global PN_STORED(1) * out, MomentsParams p) {
  MOMENTS_TEXEL(p);
  PN_STORE(1, out, texel, moments_encode(depth[texel], p, MOMENTS_KIND_ESM).x);
}

// EVSM2: the positive warp only, (e^(c+ x), e^(2 c+ x)).
__kernel void moments_evsm2(__global const float* depth, __global Stored2* out, MomentsParams p) {
  MOMENTS_TEXEL(p);
  PN_STORE(2, out, texel, moments_encode(depth[texel], p, MOMENTS_KIND_EVSM2).xy);
}

// EVSM4: both warps, (pos, pos^2, neg, neg^2).
__kernel void moments_evsm4(__global const float* depth, __global Stored4* out, MomentsParams p) {
  MOMENTS_TEXEL(p);
  PN_STORE(4, out, texel, moments_encode(depth[texel], p, MOMENTS_KIND_EVSM4));
}

// LVSM: plane `l` holds (phi_l(d), phi_l(d)^2) for the layer [p_l, q_l] given in normalised depth.
__kernel void moments_lvsm(__global const float* depth, __global float2* out, __constant float2* layers,
                           MomentsParams p) {
  MOMENTS_TEXEL(p);
  float d = moments_normalize(depth[texel], p.depthNear, p.depthInvRange);
  uint plane = p.width * p.height;
  for (uint l = 0; l < p.layerCount; ++l) {
    float w = moments_layer_warp(d, layers[l]);
    out[l * plane + texel] = (float2)(w, w * w);
  }
}

// MSM: four power moments through the quantization transform.
__kernel void moments_msm(__global const float* depth, __global Stored4* out, MomentsParams p) {
  MOMENTS_TEXEL(p);
  PN_STORE(4, out, texel, moments_encode(depth[texel], p, MOMENTS_KIND_MSM));
}

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
