// Moment shadow maps, Hamburger 4MSM (Peters & Klein, "Moment Shadow Mapping", I3D 2015, sec. 3-4 and
// Algorithm 2): from four filtered power moments b of normalised depth, the sharpest lower bound on the
// shadow intensity P(x < z_f) over all depth distributions with these moments. The moments are stored
// through the quantization transform of kernels/shared/moments.h and decoded first.
#include "kernels/shared/chebyshev.h"
#include "kernels/shared/moment_map.h"
#include "kernels/shared/moments.h"

// Moments b1..b4 of depths 0, 1/2, 1 with weights 1/4, 1/2, 1/4: the target of the moment bias.
#define MSM_BIAS_TARGET (float4)(0.5f, 0.375f, 0.3125f, 0.28125f)

// Algorithm 2. (1) Bias b towards MSM_BIAS_TARGET by the share alpha. Three support points give the target
// a positive definite Hankel matrix B = [1 b1 b2; b1 b2 b3; b2 b3 b4], so the biased B is positive definite
// for any data, also for depths exactly at the normalisation's ends (the nearest caster is 0, background
// 1), where a two-point target such as (1/2, 1/2, 1/2, 1/2) leaves it singular. (2) Solve B c =
// (1, z_f, z_f^2) by an LDL^T (Cholesky) factorisation. (3) The roots z2 <= z3 of c1 + c2 z + c3 z^2 are the
// other two support points of the three-point distribution {z_f, z2, z3} that matches b. (4-6) The bound is
// the weight of the points in front of z_f; a point's weight follows from matching moments 0..2
// (Lagrange form), e.g. w2 = (z_f z3 - b1 (z_f + z3) + b2) / ((z3 - z2) (z_f - z2)).
inline float msm_hamburger(float4 b, float zf, float alpha) {
  b = mix(b, MSM_BIAS_TARGET, alpha);
  float d2 = b.y - b.x * b.x;                   // D22
  float l32 = (b.z - b.x * b.y) / d2;           // L32
  float d3 = b.w - b.y * b.y - l32 * l32 * d2;  // D33
  float c2 = zf - b.x;                          // forward substitution, L y = (1, z_f, z_f^2)
  float c3 = zf * zf - b.y - l32 * c2;
  c2 /= d2;  // D^-1
  c3 /= d3;
  c2 -= l32 * c3;  // back substitution, L^T c = y
  float c1 = 1.0f - b.x * c2 - b.y * c3;
  float p = c2 / c3, q = c1 / c3;
  float r = sqrt(max(0.25f * p * p - q, 0.0f));
  float z2 = -0.5f * p - r, z3 = -0.5f * p + r;
  if (zf <= z2) return 0.0f;
  if (zf <= z3) return (zf * z3 - b.x * (zf + z3) + b.y) / ((z3 - z2) * (zf - z2));
  return 1.0f - (z2 * z3 - b.x * (z2 + z3) + b.y) / ((zf - z2) * (zf - z3));
}

// Shadow intensity with the bias's own share removed. The biased moments are those of (1 - alpha) P +
// alpha T with T the three-point target, so any bound G from them satisfies G <= (1 - alpha) G_P +
// alpha T(x < z_f) <= (1 - alpha) G_P + alpha, where G_P is the bound for P itself: (G - alpha) / (1 - alpha)
// is still a lower bound for P. It is exactly 0 on lit surfaces instead of up to alpha, and absorbs the fp32
// noise of the decoded moments (~1e-6 in G).
inline float msm_shadow(float4 b, float zf, float alpha) {
  float g = msm_hamburger(b, zf, alpha);
  return isnan(g) ? 0.0f : clamp((g - alpha) / (1.0f - alpha), 0.0f, 1.0f);
}

__kernel void msm_visibility(__global const float4* position, __global const float4* normal,
                             __constant const LightViewGpu* lv, __global const MomentScalar* base,
                             __global const MomentScalar* mips, __constant const PyramidLevel* mipLevels, MomentShade s,
                             __global float* visibility, __global float4* debugMoments, __global float2* debugStats) {
  uint i = get_global_id(0);
  if (i >= s.width * s.height) return;
  mm_prefetch(position, lv, base, s, i);
  MomentReceiver r = mm_receiver(position, normal, lv, s, i);
  float lit = 1.0f, variance = 0.0f, width = 0.0f;
  float4 b = (float4)(0.0f);
  if (r.valid) {
    b = moments_msm_decode(mm_lookup(base, mips, mipLevels, lv, s, &r, &width));
    variance = b.y - b.x * b.x;
    lit = cheb_reduce_bleeding(1.0f - msm_shadow(b, r.t, s.momentBias), s.bleeding);
  }
  mm_store(i, lit, b, variance, width, visibility, debugMoments, debugStats);
}
