// Hard shadow mapping (Williams 1978) with constant, slope-scaled and normal-offset bias: one nearest-texel
// depth comparison per pixel of the camera's G-buffer.
#include "kernels/shared/shadow_common.h"

__kernel void sm_visibility(__global const float4* position, __global const float4* normal, uint count,
                            __global const float* map, __constant const LightViewGpu* lv, float biasConstant,
                            float biasSlope, float normalOffset, __global float* visibility) {
  uint i = get_global_id(0);
  if (i >= count) return;
  float4 p = position[i];
  if (p.w == 0.0f) {  // background
    visibility[i] = 1.0f;
    return;
  }
  ShadowBias bias = {biasConstant, biasSlope, normalOffset};
  Receiver r = sc_receiver(lv, p.xyz, normal[i].xyz, bias);
  float lit = 1.0f;
  if (r.valid) {
    float occluder = sc_fetch(map, lv->width, lv->height, (int)floor(r.uv.x), (int)floor(r.uv.y));
    lit = sc_lit(occluder, r.depth - r.bias);
  }
  visibility[i] = lit;
}
