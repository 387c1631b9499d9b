// Pyramids: mip chains of moments (exact area averages, odd sizes included, so every level keeps the
// mean) and the min-max depth pyramid of a hierarchical shadow map (VSSM, Yang et al. 2010, sec. 4):
// conservative min/max over every texel a footprint touches. One launch per level.
#include "kernels/shared/pyramid.h"

#ifndef PYRAMID_CHANNELS
#define PYRAMID_CHANNELS 1
#endif
#define PYRAMID_T PN_VEC(float, PYRAMID_CHANNELS)

__kernel void pyramid_downsample(__global const PYRAMID_T* src, PyramidLevel s, __global PYRAMID_T* dst,
                                 PyramidLevel d) {
  const uint x = get_global_id(0), y = get_global_id(1);
  if (x >= d.width || y >= d.height) return;
  int x0, y0;
  float wx[3], wy[3];
  const int nx = pyramid_taps(x, s.width, d.width, &x0, wx), ny = pyramid_taps(y, s.height, d.height, &y0, wy);
  PYRAMID_T sum = 0.0f;
  for (int j = 0; j < ny; ++j) {
    PYRAMID_T row = 0.0f;
    for (int i = 0; i < nx; ++i) row += wx[i] * src[s.offset + (size_t)(y0 + j) * s.width + x0 + i];
    sum += wy[j] * row;
  }
  dst[d.offset + (size_t)y * d.width + x] = sum;
}

// Base level: (d, d) for a drawn texel, the empty interval (+INF, -INF) for background and NaN.
__kernel void pyramid_minmax_base(__global const float* depth, __global float2* out, PyramidLevel d) {
  const uint x = get_global_id(0), y = get_global_id(1);
  if (x >= d.width || y >= d.height) return;
  const size_t i = (size_t)y * d.width + x;
  const float z = depth[i];
  out[d.offset + i] = isfinite(z) ? (float2)(z, z) : (float2)(INFINITY, -INFINITY);
}

__kernel void pyramid_minmax_down(__global const float2* src, PyramidLevel s, __global float2* dst, PyramidLevel d) {
  const uint x = get_global_id(0), y = get_global_id(1);
  if (x >= d.width || y >= d.height) return;
  int x0, y0;
  float wx[3], wy[3];
  const int nx = pyramid_taps(x, s.width, d.width, &x0, wx), ny = pyramid_taps(y, s.height, d.height, &y0, wy);
  float2 range = (float2)(INFINITY, -INFINITY);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const float2 v = src[s.offset + (size_t)(y0 + j) * s.width + x0 + i];
      range = (float2)(fmin(range.x, v.x), fmax(range.y, v.y));
    }
  dst[d.offset + (size_t)y * d.width + x] = range;
}
