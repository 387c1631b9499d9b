// LVSM layer placement samples (Lauritzen & McCool, GI 2008, sec. 4.1 and 5), one work-item per 2x2
// neighbourhood of the light's depth map: the neighbourhood's unwarped VSM moments are the bilinear sample
// between the four texels (sec. 5), from which
//   lvsm_lloyd_samples: the "second occluder" depth mu + sigma (exact, max{a, b}, for two depths at alpha = 1/2)
//                       weighted by the variance sigma^2 (sec. 4.1), for the weighted k-means of the splits;
//   lvsm_leak_samples:  our leak metric: the layered Chebyshev bound (eqs. 3, 6, 7) for a receiver `leakGap`
//                       behind the neighbourhood's farthest depth, whose true visibility is 0 (eq. 4's tail),
//                       weighted by the same variance.
// Neighbourhoods touching an empty texel (nothing drawn) are skipped (weight 0): nothing lies behind them.
#include "kernels/shared/chebyshev.h"
#include "kernels/shared/lvsm.h"

typedef struct LvsmNeighbourhood {
  float d[4];            // normalised depths
  float mean, variance;  // unwarped moments of the four
  int valid;
} LvsmNeighbourhood;

inline LvsmNeighbourhood lvsm_neighbourhood(__global const float* depth, MomentsParams p, uint x, uint y) {
  LvsmNeighbourhood n;
  n.valid = 1;
  float m1 = 0.0f, m2 = 0.0f;
  for (int k = 0; k < 4; ++k) {
    float raw = depth[(y + (k >> 1)) * p.width + x + (k & 1)];
    n.valid &= isfinite(raw);
    n.d[k] = moments_normalize(raw, p.depthNear, p.depthInvRange);
    m1 += 0.25f * n.d[k];
    m2 += 0.25f * n.d[k] * n.d[k];
  }
  n.mean = m1;
  n.variance = max(m2 - m1 * m1, 0.0f);
  return n;
}

#define LVSM_SAMPLE(p)                                         \
  uint x = get_global_id(0), y = get_global_id(1);             \
  if (x + 1 >= (p).width || y + 1 >= (p).height) return;       \
  uint sample = y * ((p).width - 1) + x

// Samples (x, w) for reduceLloydStats; w = 0 (skipped) below the minimum variance: flat or empty regions.
__kernel void lvsm_lloyd_samples(__global const float* depth, MomentsParams p, float minVariance,
                                 __global float* outX, __global float* outW) {
  LVSM_SAMPLE(p);
  LvsmNeighbourhood n = lvsm_neighbourhood(depth, p, x, y);
  bool use = n.valid && n.variance > minVariance;
  outX[sample] = n.mean + sqrt(n.variance);
  outW[sample] = use ? n.variance : 0.0f;
}

// Per neighbourhood: the bound leaking onto a receiver at t = max depth + gap in the layer holding t.
__kernel void lvsm_leak_samples(__global const float* depth, MomentsParams p, __constant const LvsmLayout* L,
                                __global float* outLeak, __global float* outW) {
  LVSM_SAMPLE(p);
  LvsmNeighbourhood n = lvsm_neighbourhood(depth, p, x, y);
  float far = max(max(n.d[0], n.d[1]), max(n.d[2], n.d[3]));
  float t = far + L->leakGap;
  bool use = n.valid && n.variance > L->minVariance && t <= 1.0f;
  int i = lvsm_layer_of(L, t);
  float2 interval = lvsm_interval(L, i);
  float2 m = (float2)(0.0f);
  for (int k = 0; k < 4; ++k) {
    float w = moments_layer_warp(n.d[k], interval);
    m += 0.25f * (float2)(w, w * w);
  }
  float minVariance = lvsm_min_variance(interval, L->minVariance);
  outLeak[sample] = cheb_upper_bound(m, moments_layer_warp(t, interval), minVariance);
  outW[sample] = use ? n.variance : 0.0f;
}
