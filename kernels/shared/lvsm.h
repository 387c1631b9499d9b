// Layered variance shadow maps (Lauritzen & McCool, GI 2008): the layer layout shared by the LVSM kernels
// and the host — split sequence s_0 = 0 < s_1 < .. < s_N = 1 in normalised depth (sec. 3.4), the widened
// layer intervals [p_i, q_i] of the eq. 6 warps, and the transition half-width around each split (sec. 5).
#ifndef PENUMBRA_KERNELS_SHARED_LVSM_H
#define PENUMBRA_KERNELS_SHARED_LVSM_H

#include "kernels/shared/common.h"
#include "kernels/shared/moments.h"

#define LVSM_SPLIT_SLOTS 20  // >= MOMENTS_MAX_LAYERS + 1 split values, padded to keep `layer` 16-byte aligned

typedef struct LvsmLayout {
  uint count;          // layers N, 1..MOMENTS_MAX_LAYERS
  uint uniform;        // 1: s_i = i / N exactly, so the receiver's layer is floor(t N) (sec. 5, "directly")
  uint planeFloats;    // floats per layer of the base level (width * height * 2)
  uint mipFloats;      // floats per layer of the mip chain (0 without mips)
  float transition;    // half-width of the blend region around each interior split, normalised depth
  float minVariance;   // the global sigma^2_min of eq. 7, normalised depth^2
  float leakGap;       // leak metric: hypothetical receiver this far behind the farthest occluder
  float pad0;
  float split[LVSM_SPLIT_SLOTS];     // s_0..s_N
  float layer[2 * MOMENTS_MAX_LAYERS];  // p_0, q_0, p_1, q_1, ...: split intervals widened by +-delta
} LvsmLayout;

#if PENUMBRA_HOST
static_assert(sizeof(LvsmLayout) == 32 + 4 * LVSM_SPLIT_SLOTS + 8 * MOMENTS_MAX_LAYERS,
              "LvsmLayout layout is shared with OpenCL C");
static_assert(offsetof(LvsmLayout, split) == 32 && offsetof(LvsmLayout, layer) == 112);
#else

// The layer whose split interval [s_i, s_{i+1}) holds depth t: uniform splits by direct index, general splits
// by a binary search of the monotonic split sequence (sec. 5).
inline int lvsm_layer_of(__constant const LvsmLayout* L, float t) {
  int n = (int)L->count;
  if (L->uniform) return clamp((int)floor(t * (float)n), 0, n - 1);
  int lo = 0, hi = n - 1;  // answer in [lo, hi]: the number of interior splits s_1..s_{N-1} <= t
  while (lo < hi) {
    int mid = (lo + hi + 1) / 2;
    if (L->split[mid] <= t) lo = mid;
    else hi = mid - 1;
  }
  return lo;
}

// Layer i's warp interval [p_i, q_i] (eq. 6 with the sec. 3.4 overlaps).
inline float2 lvsm_interval(__constant const LvsmLayout* L, int i) {
  return (float2)(L->layer[2 * i], L->layer[2 * i + 1]);
}

// Eq. 7: the layer's minimum variance, sigma^2_min / (q_i - p_i)^2.
inline float lvsm_min_variance(float2 interval, float minVariance) {
  float range = interval.y - interval.x;
  return minVariance / (range * range);
}

#endif
#endif
