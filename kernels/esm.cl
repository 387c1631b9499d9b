// Exponential shadow maps (Annen, Mertens, Seidel, Flerackers, Kautz, "Exponential Shadow Maps", GI 2008,
// sec. 3): for occluders in front of the receiver, s(d, t) = e^(c (d - t)) is a smooth stand-in
// for the step H(d - t), and filtering e^(c d) filters the test: visibility = clamp(E[e^(c x)] e^(-c t), 0, 1).
// The moments are the EVSM positive warp of x = 2d - 1 (kernels/shared/moments.h), so c here is half the
// exponent of the paper's [0, 1] depth. Fails where the receiver lies behind its own neighbourhood
// (non-planar receivers, contact): the assumption d <= t breaks and the result over-darkens or leaks.
#include "kernels/shared/moment_map.h"
#include "kernels/shared/moments.h"

__kernel void esm_visibility(__global const float4* position, __global const float4* normal,
                             __constant const LightViewGpu* lv, __global const MomentScalar* base,
                             __global const MomentScalar* mips, __constant const PyramidLevel* mipLevels, MomentShade s,
                             __global float* visibility, __global float4* debugMoments, __global float2* debugStats) {
  uint i = get_global_id(0);
  if (i >= s.width * s.height) return;
  MomentReceiver r = mm_receiver(position, normal, lv, s, i);
  float lit = 1.0f, width = 0.0f;
  float4 m = (float4)(0.0f);
  if (r.valid) {
    m = mm_lookup(base, mips, mipLevels, lv, s, &r, &width);
    float x = 2.0f * r.t - 1.0f;
    // In the log domain: E[e^(c x)] up to e^42 times e^(-c t) up to e^42 would overflow fp32.
    lit = m.x > 0.0f ? exp(min(log(m.x) - s.expPositive * x, 0.0f)) : 0.0f;
  }
  mm_store(i, lit, m, 0.0f, width, visibility, debugMoments, debugStats);
}
