// Exponential variance shadow maps (Lauritzen & McCool, "Layered Variance Shadow Maps", GI 2008, sec. 7):
// the Chebyshev bound (kernels/shared/chebyshev.h) applied to moments of the warps e^(c+ x) and -e^(-c- x),
// x = 2d - 1 (kernels/shared/moments.h). evsm2 uses the positive warp; evsm4 takes the minimum of both
// bounds, each an upper bound on the lit fraction because both warps are monotonic (sec. 3.2).
#include "kernels/shared/chebyshev.h"
#include "kernels/shared/moment_map.h"
#include "kernels/shared/moments.h"

// The bound of one warp. The minimum variance is given in normalised depth units and carried through the
// warp by its squared derivative at the filtered mean (dw/dd = 2 c |w|), the exponential analogue of the
// linear-warp rule (sigma_min^2)_i = sigma_min^2 / (q_i - p_i)^2 of LVSM eq. 7.
inline float evsm_bound(float2 moments, float warpedT, float c, MomentShade s, float* variance) {
  float slope = 2.0f * c * fabs(moments.x);
  float minVariance = slope * slope * s.minVariance;
  *variance = cheb_variance(moments, minVariance);
  return cheb_reduce_bleeding(cheb_upper_bound(moments, warpedT, minVariance), s.bleeding);
}

// evsm2 (2 moment channels: the positive warp) and evsm4 (4 channels: both warps, the smaller bound).
__kernel void evsm_visibility(__global const float4* position, __global const float4* normal,
                              __constant const LightViewGpu* lv, __global const MomentScalar* base,
                              __global const MomentScalar* mips, __constant const PyramidLevel* mipLevels,
                              MomentShade s, __global float* visibility, __global float4* debugMoments,
                              __global float2* debugStats) {
  uint i = get_global_id(0);
  if (i >= s.width * s.height) return;
  mm_prefetch(position, lv, base, s, i);
  MomentReceiver r = mm_receiver(position, normal, lv, s, i);
  float lit = 1.0f, variance = 0.0f, width = 0.0f;
  float4 m = (float4)(0.0f);
  if (r.valid) {
    m = mm_lookup(base, mips, mipLevels, lv, s, &r, &width);
    float2 t = moments_evsm_warp(r.t, s.expPositive, s.expNegative);
    lit = evsm_bound(m.xy, t.x, s.expPositive, s, &variance);
    if (s.channels == 4) {
      float negativeVariance;
      lit = min(lit, evsm_bound(m.zw, t.y, s.expNegative, s, &negativeVariance));
    }
  }
  mm_store(i, lit, m, variance, width, visibility, debugMoments, debugStats);
}
