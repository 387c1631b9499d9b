// Visibility bounds from filtered depth moments, shared by every variance-based technique (vsm, savsm,
// evsm2/4, lvsm, psvsm, vssm). OpenCL C only.
//
// Donnelly & Lauritzen, "Variance Shadow Maps" (I3D 2006), eq. 5: for a receiver at depth t and filtered
// moments M1 = E[x], M2 = E[x^2] of the occluder depth x, the one-sided Chebyshev (Cantelli) inequality
//   P(x >= t) <= p_max(t) = sigma^2 / (sigma^2 + (t - mu)^2),  sigma^2 = M2 - M1^2,
// holds for t > mu; for t <= mu the receiver is treated as fully lit. The bound is exact for a single
// planar occluder over a single planar receiver parallel to it (the "planar" case of the VSM paper).
#ifndef PENUMBRA_KERNELS_SHARED_CHEBYSHEV_H
#define PENUMBRA_KERNELS_SHARED_CHEBYSHEV_H

#include "kernels/shared/common.h"

#if !PENUMBRA_HOST

// sigma^2 of the moments, clamped below by `minVariance` (the VSM paper's sec. 3.2 numeric guard against
// the catastrophic cancellation in M2 - M1^2).
inline float cheb_variance(float2 moments, float minVariance) {
  return max(moments.y - moments.x * moments.x, minVariance);
}

// Upper bound on the lit fraction at depth t: 1 when t <= mu, Cantelli otherwise. NaN moments give 1
// (nothing known about occluders) so a NaN can never reach the image.
inline float cheb_upper_bound(float2 moments, float t, float minVariance) {
  float mu = moments.x;
  if (!(t > mu)) return 1.0f;  // also NaN mu or t
  float variance = cheb_variance(moments, minVariance);
  float d = t - mu;
  float p = variance / (variance + d * d);
  return isnan(p) ? 1.0f : clamp(p, 0.0f, 1.0f);
}

// Light-bleeding reduction (Lauritzen, GPU Gems 3 ch. 8 "Summed-Area Variance Shadow Maps", sec. 8.4.3):
// linstep(amount, 1, p) cuts the tail of the bound below `amount` to 0 and rescales the rest; amount = 0
// leaves p unchanged. Over-darkens penumbrae as amount grows.
inline float cheb_reduce_bleeding(float p, float amount) {
  if (amount <= 0.0f) return p;
  return clamp((p - amount) / (1.0f - amount), 0.0f, 1.0f);
}

#endif
#endif
