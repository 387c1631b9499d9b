// Percentage-closer filtering (Reeves et al. 1987): the fraction of depth comparisons that pass over a
// (2r+1)^2 grid of bilinear-weighted taps around the receiver; the depth bias grows with the tap offset
// (slope-scaled) so tilted planar receivers do not shadow themselves.
#include "kernels/shared/shadow_common.h"

__kernel void pcf_visibility(__global const float4* position, __global const float4* normal, uint count,
                             __global const float* map, __constant const LightViewGpu* lv, float biasConstant,
                             float biasSlope, float normalOffset, int radius, __global float* visibility) {
  uint i = get_global_id(0);
  if (i >= count) return;
  float4 p = position[i];
  if (p.w == 0.0f) {
    visibility[i] = 1.0f;
    return;
  }
  ShadowBias bias = {biasConstant, biasSlope, normalOffset};
  Receiver r = sc_receiver(lv, p.xyz, normal[i].xyz, bias);
  if (!r.valid) {
    visibility[i] = 1.0f;
    return;
  }
  float sum = 0.0f;
  for (int dy = -radius; dy <= radius; ++dy)
    for (int dx = -radius; dx <= radius; ++dx) {
      float offset = sqrt((float)(dx * dx + dy * dy));
      float depth = r.depth - r.bias - r.biasSlope * offset;
      sum += sc_compare_bilinear(map, lv->width, lv->height, r.uv + (float2)(dx, dy), depth);
    }
  float taps = (float)((2 * radius + 1) * (2 * radius + 1));
  visibility[i] = sum / taps;
}
