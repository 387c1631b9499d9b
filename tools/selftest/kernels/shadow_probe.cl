// Probe of the receiver's depth slope (kernels/shared/shadow_common.h) for tests/shadow_slope_test.cpp.
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
