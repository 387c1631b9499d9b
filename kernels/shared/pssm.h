// Parallel-split shadow maps (pssm, psvsm): the per-split constants every split kernel reads, split selection with
// one split per 2x2 pixel quad (Lauritzen, "Parallel-Split Variance Shadow Maps", sec. "Texture coordinate
// derivatives": a compute kernel has explicit quads), the blend band across split planes, and the resolution
// error AOV (Luksch sec. 6.3, eq. 5: the minimum distance to neighbouring fragments in the map). Host and kernels.
#ifndef PENUMBRA_KERNELS_SHARED_PSSM_H
#define PENUMBRA_KERNELS_SHARED_PSSM_H

#include "kernels/shared/common.h"

#define PSSM_MAX_SPLITS 16  // choices of --pssm-splits and --pssm-max-splits

// One split's constants (the light view of split s is lightViews[s], its map the s-th map of the atlas).
typedef struct PssmSplit {
  float nearDistance, farDistance;  // camera view-depth range C_s .. C_{s+1}
  float filterScale;                // texel_0 / texel_s: filter offsets in texels of split 0 become this many of s
  float blurSigma;                  // psvsm: standard deviation of this split's moment blur, its own texels
  float depthNear, depthInvRange;   // psvsm: the moments' normalisation of this split's map
  float pad0, pad1;
} PssmSplit;

// Per-frame arguments of the split kernels (by value).
typedef struct PssmShade {
  uint width, height;  // G-buffer pixels (row 0 at the bottom)
  uint splits;         // 1..PSSM_MAX_SPLITS
  uint mapTexels;      // texels of one split's map (size^2): split s starts at s * mapTexels
  uint mipTexels;      // psvsm: texels of one split's mip chain (levels 1..)
  float blend;         // blend band: the last `blend` fraction of a split's depth range fades into the next; 0 = off
  float bias, slopeBias, normalOffset;  // ShadowBias, texel footprints of the split used
  int radius;                           // pssm: PCF taps a side ((2 radius + 1)^2); 0 = one hard comparison
  int idMode;                           // pssm: ID_BUFFER_* (kernels/shared/id_buffer.h)
  float pcfWidth;                       // pssm: the PCF kernel's half-width in texels of split 0 (>= radius)
} PssmShade;

#if PENUMBRA_HOST
static_assert(sizeof(PssmSplit) == 32, "PssmSplit layout is shared with OpenCL C");
static_assert(sizeof(PssmShade) == 48 && offsetof(PssmShade, blend) == 20 && offsetof(PssmShade, idMode) == 40,
              "PssmShade layout is shared with OpenCL C");
#else
#include "kernels/shared/moment_map.h"

// The split whose depth range holds view depth `z` (clamped to the first and last split).
inline int pssm_split_of(__constant const PssmSplit* splits, uint count, float z) {
  int s = 0;
  while (s + 1 < (int)count && z >= splits[s].farDistance) ++s;
  return s;
}

// The split of pixel i's 2x2 quad: the farthest split of its covered pixels, the most conservative choice (its
// map covers the widest area), shared by all four so filter footprints never mix splits. -1: no covered pixel.
inline int pssm_quad_split(__global const float4* position, __global const float* depth,
                           __constant const PssmSplit* splits, PssmShade s, uint i) {
  uint x0 = (i % s.width) & ~1u, y0 = (i / s.width) & ~1u;
  int split = -1;
  for (uint dy = 0; dy < 2; ++dy)
    for (uint dx = 0; dx < 2; ++dx) {
      uint x = x0 + dx, y = y0 + dy;
      if (x >= s.width || y >= s.height) continue;
      uint j = y * s.width + x;
      if (position[j].w != 0.0f) split = max(split, pssm_split_of(splits, s.splits, depth[j]));
    }
  return split;
}

// Weight of the next split for a pixel at view depth z in split `split`: 0 outside the blend band, rising
// linearly to 1 at the split's far plane (where the next split takes over alone).
inline float pssm_blend_weight(__constant const PssmSplit* splits, PssmShade s, int split, float z) {
  if (s.blend <= 0.0f || split + 1 >= (int)s.splits) return 0.0f;
  float range = splits[split].farDistance - splits[split].nearDistance;
  float t = (z - (splits[split].farDistance - s.blend * range)) / (s.blend * range);
  return clamp(t, 0.0f, 1.0f);
}

// Resolution error: log2(texel size / pixel footprint), from the shorter of the screen-x and screen-y steps to
// on-plane neighbours in the split's map (Luksch eq. 5 takes the minimum neighbour distance). > 0: one texel
// covers 2^e pixels (undersampled); <= 0: at least one texel per pixel. 0 when no neighbour qualifies.
inline float pssm_resolution_error(__global const float4* position, __constant const LightViewGpu* lv, PssmShade s,
                                   uint i, float3 p, float3 n) {
  Footprint f = sc_footprint(position, lv, s.width, s.height, i, p, n);
  float lx = length(f.dx.xy), ly = length(f.dy.xy);
  float step = lx > 0.0f && ly > 0.0f ? min(lx, ly) : max(lx, ly);
  return step > 0.0f ? -log2(step) : 0.0f;
}

// Per-pixel AOVs: split index (-1 background) and resolution error.
inline void pssm_store_aovs(uint i, int split, float error, __global float* splitIndex,
                            __global float* resolutionError) {
  splitIndex[i] = (float)split;
  resolutionError[i] = isfinite(error) ? error : 0.0f;
}

#endif
#endif
