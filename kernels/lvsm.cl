// Layered variance shadow maps (Lauritzen & McCool, GI 2008): the receiver's layer is found from its depth
// (sec. 5: uniform splits by index, others by searching the splits), its depth warped by that layer's eq. 6,
// one moment lookup in that layer and the Chebyshev bound of eq. 3 with the layer's minimum variance (eq. 7).
// Near a split, the two adjacent layers' bounds are blended (sec. 5, "transition region"). Layers are stored
// plane-major as fp32, or as 16-bit unorm with -DLVSM_UNORM16 (sec. 5: "16-bit per component fixed-point").
#include "kernels/shared/chebyshev.h"
#include "kernels/shared/lvsm.h"
#include "kernels/shared/moment_map.h"

#ifdef LVSM_UNORM16
typedef ushort LvsmTexel;

inline float2 lvsm_fetch16(__global const ushort* data, PyramidLevel l, int x, int y) {
  x = clamp(x, 0, (int)l.width - 1);
  y = clamp(y, 0, (int)l.height - 1);
  size_t texel = (size_t)l.offset + (size_t)y * l.width + (size_t)x;
  return convert_float2(vload2(0, data + 2 * texel)) * (1.0f / 65535.0f);
}

// Bilinear lookup as mm_bilinear, from unorm16 texels (the filtering runs in fp32, like texture units do).
inline float2 lvsm_bilinear16(__global const ushort* data, PyramidLevel l, float2 uv) {
  float2 t = uv - 0.5f;
  float2 base = floor(t);
  float2 f = t - base;
  int x = (int)base.x, y = (int)base.y;
  float2 bottom = mix(lvsm_fetch16(data, l, x, y), lvsm_fetch16(data, l, x + 1, y), f.x);
  float2 top = mix(lvsm_fetch16(data, l, x, y + 1), lvsm_fetch16(data, l, x + 1, y + 1), f.x);
  return mix(bottom, top, f.y);
}

// Trilinear lookup as mm_sample.
inline float4 lvsm_sample(__global const ushort* base, __global const ushort* mips,
                          __constant const PyramidLevel* mipLevels, __constant const LightViewGpu* lv, MomentShade s,
                          float2 uv, float footprint) {
  float lod = mm_lod(s, footprint);
  int k = min((int)lod, (int)s.levels - 1);
  float f = lod - (float)k;
  PyramidLevel l0 = mm_level(lv, mipLevels, k);
  float2 scale0 = (float2)((float)l0.width / (float)lv->width, (float)l0.height / (float)lv->height);
  float2 m = lvsm_bilinear16(k == 0 ? base : mips, l0, uv * scale0);
  if (f > 0.0f && k + 1 < (int)s.levels) {
    PyramidLevel l1 = mm_level(lv, mipLevels, k + 1);
    float2 scale1 = (float2)((float)l1.width / (float)lv->width, (float)l1.height / (float)lv->height);
    m = mix(m, lvsm_bilinear16(mips, l1, uv * scale1), f);
  }
  return (float4)(m, 0.0f, 0.0f);
}
#else
typedef float LvsmTexel;
#define lvsm_sample mm_sample
#endif

// mm_lookup's first half: the filter width and the receiver-plane bias of r->t, before the layer is known.
inline void lvsm_filter_receiver(MomentShade s, MomentReceiver* r, float* width) {
  float lod = mm_lod(s, r->footprint);
  float size = exp2(floor(lod)), f = lod - floor(lod);
  *width = size * (1.0f + f);
  float sigma = sqrt(s.blurSigma * s.blurSigma + 0.25f * size * size * (1.0f + 3.0f * f));
  r->t = mm_filtered_t(*r, s, sigma);
}

// Layer i's bound at receiver depth t (unwarped): eq. 6 warp of t, one lookup, eq. 3 with eq. 7's variance.
inline float lvsm_layer_bound(__global const LvsmTexel* base, __global const LvsmTexel* mips,
                              __constant const PyramidLevel* mipLevels, __constant const LightViewGpu* lv,
                              MomentShade s, __constant const LvsmLayout* L, MomentReceiver r, int i, float4* m,
                              float* variance) {
  float2 interval = lvsm_interval(L, i);
  *m = lvsm_sample(base + (size_t)i * L->planeFloats, mips + (size_t)i * L->mipFloats, mipLevels, lv, s, r.uv,
                   r.footprint);
  float minVariance = lvsm_min_variance(interval, s.minVariance);
  *variance = cheb_variance(m->xy, minVariance);
  float t = moments_layer_warp(r.t, interval);
  return cheb_reduce_bleeding(cheb_upper_bound(m->xy, t, minVariance), s.bleeding);
}

__kernel void lvsm_visibility(__global const float4* position, __global const float4* normal,
                              __constant const LightViewGpu* lv, __global const LvsmTexel* base,
                              __global const LvsmTexel* mips, __constant const PyramidLevel* mipLevels, MomentShade s,
                              __constant const LvsmLayout* L, __global float* visibility, __global float4* debugMoments,
                              __global float2* debugStats, __global float* debugLayer) {
  uint i = get_global_id(0);
  if (i >= s.width * s.height) return;
  MomentReceiver r = mm_receiver(position, normal, lv, s, i);
  float lit = 1.0f, variance = 0.0f, width = 0.0f;
  float4 m = (float4)(0.0f);
  int layer = -1;
  if (r.valid) {
    lvsm_filter_receiver(s, &r, &width);
    layer = lvsm_layer_of(L, r.t);
    lit = lvsm_layer_bound(base, mips, mipLevels, lv, s, L, r, layer, &m, &variance);
    // Transition region: within `transition` of the split s_j between layers j - 1 and j, blend linearly
    // from layer j - 1's bound (at s_j - transition) to layer j's (at s_j + transition). The overlap delta
    // >= transition keeps the receiver inside both layers' linear ranges there (sec. 3.4).
    int n = (int)L->count;
    float tau = L->transition;
    int j = r.t < L->split[layer] + tau ? layer : layer + 1;  // the split nearest above or below
    if (tau > 0.0f && j >= 1 && j < n && fabs(r.t - L->split[j]) < tau) {
      float4 m2;
      float v2;
      float other = lvsm_layer_bound(base, mips, mipLevels, lv, s, L, r, j == layer ? j - 1 : j, &m2, &v2);
      float w = (r.t - (L->split[j] - tau)) / (2.0f * tau);  // weight of layer j
      lit = j == layer ? mix(other, lit, w) : mix(lit, other, w);
    }
  }
  mm_store(i, lit, m, variance, width, visibility, debugMoments, debugStats);
  debugLayer[i] = (float)layer;
}
