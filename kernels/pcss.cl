// Percentage-closer soft shadows (Fernando, "Percentage-Closer Soft Shadows", SIGGRAPH 2005 sketch):
// 1. blocker search over the region of the map the light disk subtends from the receiver, averaging the
//    depths of texels closer than the receiver; 2. penumbra width from similar triangles; 3. PCF over that
//    width. The brute-force baseline that VSSM must beat: cost grows with the search and filter tap counts.
#include "kernels/shared/shadow_common.h"

// Average depth of blockers in a square of half-width `radius` texels sampled on a taps x taps grid;
// returns 0 when no texel blocks.
inline float pcss_blocker_depth(__global const float* map, __constant const LightViewGpu* lv, Receiver r, float radius,
                                int taps) {
  float sum = 0.0f;
  int found = 0;
  float step = taps > 1 ? 2.0f * radius / (float)(taps - 1) : 0.0f;
  for (int j = 0; j < taps; ++j)
    for (int k = 0; k < taps; ++k) {
      float2 offset = taps > 1 ? (float2)(-radius + k * step, -radius + j * step) : (float2)(0.0f);
      float2 uv = r.uv + offset;
      float occluder = sc_fetch(map, lv->width, lv->height, (int)floor(uv.x), (int)floor(uv.y));
      float depth = r.depth - r.bias - r.biasSlope * length(offset);
      if (occluder < depth) {
        sum += occluder;
        ++found;
      }
    }
  return found > 0 ? sum / (float)found : 0.0f;
}

__kernel void pcss_visibility(__global const float4* position, __global const float4* normal, uint width,
                              uint height,
                              __global const float* map, __constant const LightViewGpu* lv, float biasConstant,
                              float biasSlope, float normalOffset, int receiverPlane, int searchTaps, int filterTaps, float maxRadius,
                              __global float* blockerOut, __global float* visibility) {
  uint i = get_global_id(0);
  if (i >= width * height) return;
  float4 p = position[i];
  visibility[i] = 1.0f;
  blockerOut[i] = 0.0f;
  if (p.w == 0.0f) return;
  ShadowBias bias = {biasConstant, biasSlope, normalOffset};
  float3 n = normal[i].xyz;
  Receiver r = sc_receiver(lv, p.xyz, n, bias);
  if (!r.valid) return;
  // The light disk seen from the receiver covers, at the near plane, the widest region that can hold blockers.
  float search = clamp(lv_penumbra_texels(lv, r.depth, lv->zNear), 0.5f, maxRadius);
  float blocker = pcss_blocker_depth(map, lv, r, search, searchTaps);
  blockerOut[i] = blocker;
  if (blocker <= 0.0f) return;  // no blocker: fully lit
  float radius = clamp(lv_penumbra_texels(lv, r.depth, blocker), 0.5f, maxRadius);
  ReceiverPlane rp = sc_receiver_plane_at(receiverPlane, position, lv, width, height, i, p.xyz, n, r.texel);
  const float planeBias = biasConstant * r.texel;
  float sum = 0.0f;
  float step = filterTaps > 1 ? 2.0f * radius / (float)(filterTaps - 1) : 0.0f;
  for (int j = 0; j < filterTaps; ++j)
    for (int k = 0; k < filterTaps; ++k) {
      float2 offset = filterTaps > 1 ? (float2)(-radius + k * step, -radius + j * step) : (float2)(0.0f);
      sum += sc_tap(map, lv, r, rp, planeBias, offset);
    }
  visibility[i] = sum / (float)(filterTaps * filterTaps);
}
