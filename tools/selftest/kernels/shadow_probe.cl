// Probes of kernels/shared/shadow_common.h for tests/shadow_slope_test.cpp: the receiver's depth slope and pcf's grid
// sum.
#define SHADOW_NORMAL_OFFSET_SCALED 0  // as kernels/sm.cl builds it
#include "kernels/shared/shadow_common.h"

// sc_depth_slope (kernels/shared/shadow_common.h) at given world points and normals, as sc_receiver calls
// it, so tests can check it against the light's exact ray-plane depths.
__kernel void shadow_depth_slope_test(__global const float4* points, __global const float4* normals, uint count,
                                      __constant const LightViewGpu* lv, __global float* slope) {
  uint i = get_global_id(0);
  if (i >= count) return;
  float3 p = points[i].xyz, n = normals[i].xyz;
  slope[i] = sc_depth_slope(lv, p, n, lv_texel_world_at(lv, p, max(lv_project(lv, p).z, lv->zNear)));
}

// sc_grid_plane_sum against the taps it replaces (sc_compare_bilinear_plane at every unit offset), for each receiver
// (uv, depth, plane gradient) and radius: out[2i] the taps' sum, out[2i + 1] the grid's.
__kernel void shadow_grid_plane_test(__global const float* map, int width, int height, __global const float4* receivers,
                                     __global const float2* gradients, __global const int* radii, uint count,
                                     __global float* out) {
  uint i = get_global_id(0);
  if (i >= count) return;
  const float2 uv = receivers[i].xy, g = gradients[i];
  const float depth = receivers[i].z;
  const int radius = radii[i];
  float taps = 0.0f;
  for (int dy = -radius; dy <= radius; ++dy)
    for (int dx = -radius; dx <= radius; ++dx)
      taps += sc_compare_bilinear_plane(map, width, height, uv + (float2)((float)dx, (float)dy), uv, depth, g);
  out[2 * i] = taps;
  out[2 * i + 1] = sc_grid_plane_sum(map, width, height, uv, radius, depth, g);
}
