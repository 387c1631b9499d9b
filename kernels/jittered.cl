// Confidence-based jittered shadow maps (Luksch sec. 6, after Scherzer et al. 2007): the light's map is drawn N
// times with sub-texel jitter; each pass tests every receiver against its nearest texel as sm does (or with the ID
// buffer, kernels/shared/id_buffer.h) and keeps the result of the most confident pass. Confidence of a lookup is
// its distance to the nearest texel centre (eq. 4), where the map's depth is exact. Accumulation modes (sec. 6.2,
// 6.3): simple (a pass whose confidence reaches a threshold may only add shadow), adapted (a pass replaces the kept
// result when it is more confident), optimal (adapted, with the confidence each pixel needs from the spacing of its
// G-buffer neighbours in the map, eq. 5, added so a pixel that has it is final, eq. 6). Each pass counts on the
// device, with one atomic per work-group, the pixels it changed and those still below the confidence they need:
// the host's stopping rule (sec. 6.3) reads those three counters, once a pass.
#include "kernels/shared/id_buffer.h"
#include "kernels/shared/jittered.h"
#include "kernels/shared/shadow_common.h"

// Eq. 4: 1 at a texel centre, 0 on its border (max norm), for continuous texel coordinate `uv`.
inline float jittered_confidence(float2 uv) {
  float2 f = uv - floor(uv);
  return 1.0f - 2.0f * max(fabs(f.x - 0.5f), fabs(f.y - 0.5f));
}

// Eq. 5 as 1 - optConf = precision * tcDist_min * smSize: the distance in texels (max norm, as eq. 4) from the
// pixel's map position to the nearest covered G-buffer neighbour's, times `precision` (1: the paper, a lookup
// within half a pixel spacing of its texel centre is final; smaller: stricter). The minimum over the four
// neighbours keeps the pixel's own surface at a depth discontinuity (Fig. 5); a pixel with no covered neighbour
// needs no more than its first sample (1).
__kernel void jittered_required(__global const float4* position, uint width, uint height,
                                __constant const LightViewGpu* lv, float precision, __global float* slack) {
  uint i = get_global_id(0);
  if (i >= width * height) return;
  float4 p = position[i];
  if (p.w == 0.0f) {
    slack[i] = 1.0f;
    return;
  }
  uint x = i % width, y = i / width;
  float2 here = lv_project(lv, p.xyz).xy;
  float best = INFINITY;
  for (int k = 0; k < 4; ++k) {
    int nx = (int)x + (k == 0) - (k == 1), ny = (int)y + (k == 2) - (k == 3);
    if (nx < 0 || ny < 0 || nx >= (int)width || ny >= (int)height) continue;
    float4 q = position[ny * width + nx];
    if (q.w == 0.0f) continue;
    float2 d = fabs(lv_project(lv, q.xyz).xy - here);
    float dist = max(d.x, d.y);
    if (isfinite(dist)) best = min(best, dist);
  }
  slack[i] = isfinite(best) ? min(precision * best, 1.0f) : 1.0f;
}

// One pixel's update by this pass; returns the counter flags (JITTER_COUNT_*) it raises.
inline uint jittered_update(JitterShade s, int pass, float lit, float conf, float slack, __global float* kept,
                            __global float* passOut, __global float* visibility, uint i) {
  float stored = kept[i];
  uint flags = JITTER_COUNT_COVERED;
  if (s.mode == JITTER_SIMPLE) {
    if (conf >= s.threshold) {
      kept[i] = max(stored, conf);
      if (lit == 0.0f && visibility[i] != 0.0f) {
        visibility[i] = 0.0f;
        passOut[i] = (float)(pass + 1);
        flags |= JITTER_COUNT_CHANGED;
      }
    }
    return flags | (max(stored, conf) < s.threshold ? JITTER_COUNT_UNCONFIDENT : 0u);
  }
  float c = s.mode == JITTER_OPTIMAL ? min(conf + slack, 1.0f) : conf;  // eq. 6: saturate(conf + (1 - optConf))
  if (c > stored) {
    kept[i] = c;
    visibility[i] = lit;
    passOut[i] = (float)(pass + 1);
    flags |= JITTER_COUNT_CHANGED;
  }
  return flags | (max(stored, c) < 1.0f ? JITTER_COUNT_UNCONFIDENT : 0u);
}

__kernel void jittered_accumulate(__global const float4* position, __global const float4* normal, uint width,
                                  uint height, __global const float* map, __constant const LightViewGpu* lv,
                                  float biasConstant, float biasSlope, float normalOffset, int receiverPlane,
                                  int idMode, __global const uint* mapIds, __global const uint* objectIds,
                                  __global const uint* pixelTriangle, __global const uint* pixelObject, JitterShade s,
                                  int pass, __global const float* slack, __global float* kept, __global float* passOut,
                                  __global uint* counters, __global float* visibility) {
  __local uint groupCounts[3];
  uint i = get_global_id(0), lid = get_local_id(0);
  if (lid < 3) groupCounts[lid] = 0;
  barrier(CLK_LOCAL_MEM_FENCE);
  uint flags = 0;
  float4 p = i < width * height ? position[i] : (float4)(0.0f);
  if (p.w != 0.0f) {
    ShadowBias bias = {biasConstant, biasSlope, normalOffset};
    float3 n = normal[i].xyz;
    Receiver r = sc_receiver(lv, p.xyz, n, bias);
    if (r.valid) {
      ReceiverPlane rp = sc_receiver_plane_at(receiverPlane, position, lv, width, height, i, p.xyz, n, r.texel);
      float lit = id_visibility(mapIds, objectIds, lv->width, lv->height, lv_project(lv, p.xyz).xy, pixelTriangle[i],
                                pixelObject[i], idMode, sc_hard_lit(map, lv, r, rp, biasConstant * r.texel));
      flags = jittered_update(s, pass, lit, jittered_confidence(r.uv), slack[i], kept, passOut, visibility, i);
    }
  }
  for (int k = 0; k < 3; ++k)
    if (flags & (1u << k)) atomic_inc(&groupCounts[k]);
  barrier(CLK_LOCAL_MEM_FENCE);
  if (lid < 3 && groupCounts[lid] > 0) atomic_add(&counters[lid], groupCounts[lid]);
}
