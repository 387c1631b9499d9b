// Hard shadow mapping (Williams 1978) with constant, slope-scaled and normal-offset bias, or receiver-plane
// depth bias (Isidoro, GDC 2006): one nearest-texel depth comparison per pixel of the camera's G-buffer; with an
// ID buffer (Luksch sec. 9.1, kernels/shared/id_buffer.h) the map's triangle ids decide instead, or beside it.
#define SHADOW_NORMAL_OFFSET_SCALED 0  // the whole normal offset at every angle (kernels/shared/shadow_common.h)
#include "kernels/shared/id_buffer.h"
#include "kernels/shared/shade.h"
#include "kernels/shared/shadow_common.h"

__kernel void sm_visibility(__global const float4* position, __global const float4* normal, __global const float* map,
                            __constant const LightViewGpu* lv, ShadeFrame f, __global const uint* mapIds,
                            __global const uint* objectIds, __global const uint* pixelTriangle,
                            __global const uint* pixelObject, __global float* visibility) {
  const uint width = f.width, height = f.height;
  const float biasConstant = f.biasConstant;
  const int idMode = f.idMode;
  uint i = get_global_id(0);
  if (i >= width * height) return;
  sc_prefetch_texels(position, lv, map, sizeof(float), 1, i + PN_PREFETCH_AHEAD, width * height);
  float4 p = position[i];
  if (p.w == 0.0f) {  // background
    visibility[i] = 1.0f;
    return;
  }
  ShadowBias bias = {f.biasConstant, f.biasSlope, f.normalOffset};
  float3 n = normal[i].xyz;
  // The map holds the occluder's depth at the texel centre: compare it with the receiver's own plane there.
  ReceiverPlane rp;
  Receiver r = sc_hard_receiver(f.receiverPlane, position, lv, width, height, i, p.xyz, n, bias, &rp);
  float lit = 1.0f;
  if (r.valid) {
    lit = id_visibility(mapIds, objectIds, lv->width, lv->height, id_uv(lv, p.xyz, idMode),
                        id_pixel(pixelTriangle, i, idMode), id_pixel(pixelObject, i, idMode), idMode,
                        sc_hard_lit(map, lv, r, rp, biasConstant * r.texel));
  }
  visibility[i] = lit;
}
