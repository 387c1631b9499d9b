// Summed-area variance shadow maps (Lauritzen, GPU Gems 3 ch. 8, sec. 8.5): the mean VSM moments over an
// arbitrary box come from four bilinear corner lookups of a summed-area table (Crow 1984; Hensley et al.
// 2005, sec. 4), so the filter width can change per pixel at constant cost. The width is fixed, the
// penumbra an occluder a given distance in front of the receiver casts from the light's disk (similar
// triangles, Fernando 2005), or the pixel's footprint. Built with -DSAT_MODE=... -DSAT_CHANNELS=2.
#include "kernels/shared/chebyshev.h"
#include "kernels/shared/moment_map.h"
#include "kernels/shared/sat.h"

// Box width in texels for receiver r.
inline float savsm_width(__constant const LightViewGpu* lv, MomentShade s, MomentReceiver r) {
  float width = s.filterWidth;
  if (s.widthMode == MOMENT_WIDTH_LIGHT) {
    float occluder = max(r.depth - s.occluderDistance, lv->zNear);
    width = 2.0f * lv_penumbra_texels(lv, r.depth, occluder);
  } else if (s.widthMode == MOMENT_WIDTH_FOOTPRINT) {
    width = r.footprint;
  }
  return clamp(isnan(width) ? s.filterWidth : width, s.filterWidth, s.maxWidth);
}

__kernel void savsm_visibility(__global const float4* position, __global const float4* normal,
                               __constant const LightViewGpu* lv, __global const SAT_T* sat, SatTableDesc table,
                               __global const float* satOffset, MomentShade s, __global float* visibility,
                               __global float4* debugMoments, __global float2* debugStats) {
  uint i = get_global_id(0);
  if (i >= s.width * s.height) return;
  MomentReceiver r = mm_receiver(position, normal, lv, s, i);
  float lit = 1.0f, variance = 0.0f, width = 0.0f;
  float2 m = (float2)(0.0f);
  if (r.valid) {
    width = savsm_width(lv, s, r);
    r.t = mm_filtered_t(r, s, width * (1.0f / sqrt(12.0f)));  // a box of `width` texels
    float2 reach = (float2)(0.5f * width);
    m = sat_box_mean(sat, table, satOffset, r.uv - reach, r.uv + reach);
    variance = cheb_variance(m, s.minVariance);
    lit = cheb_reduce_bleeding(cheb_upper_bound(m, r.t, s.minVariance), s.bleeding);
  }
  mm_store(i, lit, (float4)(m, 0.0f, 0.0f), variance, width, visibility, debugMoments, debugStats);
}
