// Exponential shadow maps (Annen, Mertens, Seidel, Flerackers, Kautz, "Exponential Shadow Maps", GI 2008,
// sec. 3): for occluders in front of the receiver, s(d, t) = e^(c (d - t)) is a smooth stand-in for the step
// H(d - t), and filtering e^(c d) filters the test: visibility = clamp(E[e^(c d)] e^(-c t), 0, 1), d and t the
// normalised depths in [0, 1] and c the paper's exponent. With D the filtered depth, e^(c D) = E[e^(c d)], visibility
// = e^(min(c (D - t), 0)). Up to c = 80 the map holds e^(c (d - 1)) (a normal fp32 for every d) filtered linearly, and
// D = 1 + ln(E) / c; beyond it the map holds d filtered in log space (Salvi 2008; kernels/shared/moments.h
// moments_log_mix), so any c works. A receiver whose occluder lies within ln(10) / c of it keeps more than 0.1 of the
// light (contact umbrae), and one that lies behind its own neighbourhood (non-planar receivers, contact lines) breaks
// d <= t and leaks: the larger c, the less of the first and the sharper the second.
#include "kernels/shared/moment_map.h"

__kernel void esm_visibility(__global const float4* position, __global const float4* normal,
                             __constant const LightViewGpu* lv, __global const MomentScalar* base,
                             __global const MomentScalar* mips, __constant const PyramidLevel* mipLevels, MomentShade s,
                             __global float* visibility, __global float4* debugMoments, __global float2* debugStats) {
  uint i = get_global_id(0);
  if (i >= s.width * s.height) return;
  mm_prefetch(position, lv, base, s, i);
  MomentReceiver r = mm_receiver(position, normal, lv, s, i);
  float lit = 1.0f, width = 0.0f, filtered = 0.0f;
  if (r.valid) {
    const float c = s.expPositive;
    if (s.esmLogSpace) {
      filtered = mm_lookup_log(base, mips, mipLevels, lv, s, &r, &width, c);
    } else {
      const float e = mm_lookup(base, mips, mipLevels, lv, s, &r, &width).x;  // E[e^(c (d - 1))], at least e^-80
      filtered = e > 0.0f ? 1.0f + log(e) / c : -INFINITY;
    }
    lit = exp(min(c * (filtered - r.t), 0.0f));
  }
  mm_store(i, lit, (float4)(filtered, 0.0f, 0.0f, 0.0f), 0.0f, width, visibility, debugMoments, debugStats);
}
