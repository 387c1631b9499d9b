// Parallel-split shadow maps, hard or PCF per split (Zhang et al. 2006, as summarised by Lauritzen, "Parallel-Split
// Variance Shadow Maps", steps 3-4, and Luksch sec. 7): one split per 2x2 quad, that split's light view and map,
// PCF taps scaled by the split's zoom so the filter's world footprint matches split 0, and an optional blend band.
// With an ID buffer (Luksch sec. 9.1, kernels/shared/id_buffer.h) each split's map also holds its triangle ids.
#include "kernels/shared/id_buffer.h"
#include "kernels/shared/pssm.h"
#include "kernels/shared/shadow_common.h"

// The receiver's ID-buffer inputs: the mode, the split maps' triangle ids, object id per triangle, its own ids.
typedef struct PssmIds {
  int mode;
  uint ownTriangle, ownObject;
} PssmIds;

// Visibility of world point p with normal n in split `split`; *inside = 0 when p falls outside that split's map.
inline float pssm_split_visibility(__global const float* maps, __global const uint* idMaps,
                                   __global const uint* objectIds, __constant const LightViewGpu* lightViews,
                                   __constant const PssmSplit* splits, PssmShade s, PssmIds ids, int split, float3 p,
                                   float3 n, int* inside) {
  __constant const LightViewGpu* lv = lightViews + split;
  ShadowBias bias = {s.bias, s.slopeBias, s.normalOffset};
  Receiver r = sc_receiver(lv, p, n, bias);
  *inside = r.valid && r.uv.x >= 0.0f && r.uv.y >= 0.0f && r.uv.x <= (float)lv->width && r.uv.y <= (float)lv->height;
  if (!r.valid) return 1.0f;
  __global const float* map = maps + (size_t)split * s.mapTexels;
  __global const uint* idMap = idMaps + (size_t)split * s.mapTexels;
  const float2 idUv = id_uv(lv, p, ids.mode);
  if (s.radius == 0)  // hard: the nearest texel, as sm
    return id_visibility(
        idMap, objectIds, lv->width, lv->height, idUv, ids.ownTriangle, ids.ownObject, ids.mode,
        sc_lit(sc_fetch(map, lv->width, lv->height, (int)floor(r.uv.x), (int)floor(r.uv.y)), r.depth - r.bias));
  float step = splits[split].filterScale * s.pcfWidth / (float)s.radius, sum = 0.0f;  // the taps spread over the width
  for (int dy = -s.radius; dy <= s.radius; ++dy)
    for (int dx = -s.radius; dx <= s.radius; ++dx) {
      float offset = sqrt((float)(dx * dx + dy * dy)) * step;
      float depth = r.depth - r.bias - r.biasSlope * offset;
      float2 tap = (float2)(dx, dy) * step;
      sum += id_visibility(idMap, objectIds, lv->width, lv->height, idUv + tap, ids.ownTriangle, ids.ownObject,
                           ids.mode, sc_compare_bilinear(map, lv->width, lv->height, r.uv + tap, depth));
    }
  return sum / (float)((2 * s.radius + 1) * (2 * s.radius + 1));
}

__kernel void pssm_visibility(__global const float4* position, __global const float4* normal,
                              __global const float* viewDepth, __global const float* maps,
                              __global const uint* idMaps, __global const uint* objectIds,
                              __global const uint* pixelTriangle, __global const uint* pixelObject,
                              __constant const LightViewGpu* lightViews, __constant const PssmSplit* splits,
                              PssmShade s, __global float* visibility, __global float* splitIndex,
                              __global float* resolutionError) {
  uint i = get_global_id(0);
  if (i >= s.width * s.height) return;
  float4 p = position[i];
  if (p.w == 0.0f) {
    visibility[i] = 1.0f;
    pssm_store_aovs(i, -1, 0.0f, splitIndex, resolutionError);
    return;
  }
  float3 n = normal[i].xyz;
  float z = viewDepth[i];
  int split = pssm_quad_split(position, viewDepth, splits, s, i), inside = 1;
  PssmIds ids = {s.idMode, id_pixel(pixelTriangle, i, s.idMode), id_pixel(pixelObject, i, s.idMode)};
  float lit = pssm_split_visibility(maps, idMaps, objectIds, lightViews, splits, s, ids, split, p.xyz, n, &inside);
  if (!inside) {  // a quad across a depth discontinuity: this pixel lies outside the quad's split
    split = pssm_split_of(splits, s.splits, z);
    lit = pssm_split_visibility(maps, idMaps, objectIds, lightViews, splits, s, ids, split, p.xyz, n, &inside);
  }
  float w = pssm_blend_weight(splits, s, split, z);
  if (w > 0.0f)
    lit = mix(lit,
              pssm_split_visibility(maps, idMaps, objectIds, lightViews, splits, s, ids, split + 1, p.xyz, n, &inside),
              w);
  visibility[i] = clamp(lit, 0.0f, 1.0f);
  pssm_store_aovs(i, split, pssm_resolution_error(position, lightViews + split, s, i, p.xyz, n), splitIndex,
                  resolutionError);
}
