// Parallel-split variance shadow maps (Lauritzen, "Parallel-Split Variance Shadow Maps", steps 3-7): one split per
// 2x2 quad, that split's moments (blurred by a kernel scaled with the split's zoom, step 2d, and mipmapped, 2e),
// a bilinear or trilinear lookup with the footprint measured in that split's map, and the Chebyshev bound (eq. 3).
#include "kernels/shared/chebyshev.h"
#include "kernels/shared/pssm.h"

// Visibility of pixel i in split `split`; *inside = 0 when the pixel falls outside that split's map.
inline float psvsm_split_visibility(__global const float4* position, __global const float4* normal,
                                    __constant const LightViewGpu* lightViews, __constant const PssmSplit* splits,
                                    __global const MomentScalar* base, __global const MomentScalar* mips,
                                    __constant const PyramidLevel* mipLevels, MomentShade m, PssmShade s, int split,
                                    uint i, int* inside) {
  __constant const LightViewGpu* lv = lightViews + split;
  m.depthNear = splits[split].depthNear;
  m.depthInvRange = splits[split].depthInvRange;
  m.blurSigma = splits[split].blurSigma;
  MomentReceiver r = mm_receiver(position, normal, lv, m, i);
  *inside = r.valid;
  if (!r.valid) return 1.0f;
  float width;
  float4 moments = mm_lookup(base + (size_t)split * s.mapTexels * 2, mips + (size_t)split * s.mipTexels * 2, mipLevels,
                             lv, m, &r, &width);
  return cheb_reduce_bleeding(cheb_upper_bound(moments.xy, r.t, m.minVariance), m.bleeding);
}

__kernel void psvsm_visibility(__global const float4* position, __global const float4* normal,
                               __global const float* viewDepth, __constant const LightViewGpu* lightViews,
                               __constant const PssmSplit* splits, __global const MomentScalar* base,
                               __global const MomentScalar* mips, __constant const PyramidLevel* mipLevels,
                               MomentShade m, PssmShade s, __global float* visibility, __global float* splitIndex,
                               __global float* resolutionError) {
  uint i = get_global_id(0);
  if (i >= s.width * s.height) return;
  float4 p = position[i];
  if (p.w == 0.0f) {
    visibility[i] = 1.0f;
    pssm_store_aovs(i, -1, 0.0f, splitIndex, resolutionError);
    return;
  }
  float z = viewDepth[i];
  int split = pssm_quad_split(position, viewDepth, splits, s, i), inside = 1;
  float lit =
      psvsm_split_visibility(position, normal, lightViews, splits, base, mips, mipLevels, m, s, split, i, &inside);
  if (!inside) {  // a quad across a depth discontinuity: this pixel lies outside the quad's split
    split = pssm_split_of(splits, s.splits, z);
    lit = psvsm_split_visibility(position, normal, lightViews, splits, base, mips, mipLevels, m, s, split, i, &inside);
  }
  float w = pssm_blend_weight(splits, s, split, z);
  if (w > 0.0f)
    lit = mix(lit,
              psvsm_split_visibility(position, normal, lightViews, splits, base, mips, mipLevels, m, s, split + 1, i,
                                     &inside),
              w);
  visibility[i] = isnan(lit) ? 1.0f : clamp(lit, 0.0f, 1.0f);
  pssm_store_aovs(i, split, pssm_resolution_error(position, lightViews + split, s, i, p.xyz, normal[i].xyz), splitIndex,
                  resolutionError);
}
