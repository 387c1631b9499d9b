// Hard shadow mapping (Williams 1978) with constant, slope-scaled and normal-offset bias, or receiver-plane
// depth bias (Isidoro, GDC 2006): one nearest-texel depth comparison per pixel of the camera's G-buffer.
#include "kernels/shared/shadow_common.h"

__kernel void sm_visibility(__global const float4* position, __global const float4* normal, uint width, uint height,
                            __global const float* map, __constant const LightViewGpu* lv, float biasConstant,
                            float biasSlope, float normalOffset, int receiverPlane, __global float* visibility) {
  uint i = get_global_id(0);
  if (i >= width * height) return;
  float4 p = position[i];
  if (p.w == 0.0f) {  // background
    visibility[i] = 1.0f;
    return;
  }
  ShadowBias bias = {biasConstant, biasSlope, normalOffset};
  float3 n = normal[i].xyz;
  Receiver r = sc_receiver(lv, p.xyz, n, bias);
  float lit = 1.0f;
  if (r.valid) {
    float2 texel = floor(r.uv);
    float occluder = sc_fetch(map, lv->width, lv->height, (int)texel.x, (int)texel.y);
    // The map holds the occluder's depth at the texel centre: compare it with the receiver's own plane there.
    ReceiverPlane rp = sc_receiver_plane_at(receiverPlane, position, lv, width, height, i, p.xyz, n, r.texel);
    float depth = rp.valid ? r.depth - biasConstant * r.texel + dot(rp.gradient, texel + 0.5f - r.uv) : r.depth - r.bias;
    lit = sc_lit(occluder, depth);
  }
  visibility[i] = lit;
}
