// Variance shadow maps (Donnelly & Lauritzen, I3D 2006): filtered moments (E[d], E[d^2]) of normalised
// light depth, bilinear or trilinear (mipmapped, sec. 3.1) lookups, and the one-tailed Chebyshev (Cantelli)
// bound of eq. 5 with a minimum-variance clamp (sec. 3.2) and linstep light-bleeding reduction.
#include "kernels/shared/chebyshev.h"
#include "kernels/shared/moment_map.h"

__kernel void vsm_visibility(__global const float4* position, __global const float4* normal,
                             __constant const LightViewGpu* lv, __global const MomentScalar* base,
                             __global const MomentScalar* mips, __constant const PyramidLevel* mipLevels, MomentShade s,
                             __global float* visibility, __global float4* debugMoments, __global float2* debugStats) {
  uint i = get_global_id(0);
  if (i >= s.width * s.height) return;
  mm_prefetch(position, lv, base, s, i);
  MomentReceiver r = mm_receiver(position, normal, lv, s, i);
  float lit = 1.0f, variance = 0.0f, width = 0.0f;
  float4 m = (float4)(0.0f);
  if (r.valid) {
    m = mm_lookup(base, mips, mipLevels, lv, s, &r, &width);
    variance = cheb_variance(m.xy, s.minVariance);
    lit = cheb_reduce_bleeding(cheb_upper_bound(m.xy, r.t, s.minVariance), s.bleeding);
  }
  mm_store(i, lit, m, variance, width, visibility, debugMoments, debugStats);
}
