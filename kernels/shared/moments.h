// Moment shadow-map encodings shared by the moments stage and the techniques that shade with them: the
// depth normalisation (invalid depth -> far), the EVSM exponential warps (Lauritzen, Salvi; GPU Pro 4 /
// "Exponential VSM", 2008), the LVSM layer warp (Lauritzen & McCool 2008, eq. 6) and the MSM 4-moment
// quantization transform (Peters & Klein 2015, "Moment Shadow Mapping", sec. 4 / supplementary listing).
#ifndef PENUMBRA_KERNELS_SHARED_MOMENTS_H
#define PENUMBRA_KERNELS_SHARED_MOMENTS_H

#include "kernels/shared/common.h"

// Largest EVSM exponent c such that the second warped moment e^(2c) (depth remapped to [-1,1]) and its
// filtered sums stay finite: e^(2*42) = 3.0e36 leaves a factor ~100 of headroom below FLT_MAX (3.4e38)
// for box sums; e^(2*5.54) = 65,000 is just below the largest half (65,504).
#define MOMENTS_EVSM_MAX_EXPONENT_FP32 42.0f
#define MOMENTS_EVSM_MAX_EXPONENT_FP16 5.54f
#define MOMENTS_MAX_LAYERS 16u  // LVSM layers per map (one float2 plane each)

// Single-plane encodings, as compile-time constants for kernels built per encoding (moments_encode).
#define MOMENTS_KIND_VSM 0
#define MOMENTS_KIND_EVSM2 1
#define MOMENTS_KIND_EVSM4 2
#define MOMENTS_KIND_MSM 3
#define MOMENTS_KIND_ESM 4  // ESM: one channel, e^(c (d - 1)) or (log space) the normalised depth d

// ESM's exponent c of e^(c d) on normalised depth d in [0, 1] (Annen et al. 2008's c). In log space a stored depth's
// rounding becomes a visibility error of e^(c rounding) - 1: fp32 rounds to 6e-8 (under 0.01 % at 1000). Half stores
// e^(c (d - 1)) for c in [1, 8], normal halves down to e^-8 (the smallest is e^-9.7), and d in log space below 1
// (2^-12 of rounding near 1, times c < 1).
#define MOMENTS_ESM_MAX_EXPONENT_FP32 1000.0f
#define MOMENTS_ESM_MAX_EXPONENT_FP16 8.0f
// Up to this exponent e^(c (d - 1)) >= e^-80 is a normal fp32 for every d in [0, 1], so ESM's map holds it and every
// filter (the blur stage's fused and running-sum plans, the mips, bilinear lookups) runs linearly on it, exact within
// fp32 rounding and at those filters' speed; above it the map holds d filtered in log space (kernels/blur.cl
// blur_log_*, pyramid.cl pyramid_downsample_log, moment_map.h mm_lookup_log). Below 1, e^(c (d - 1)) is so near 1 that
// its rounding over c would blur the depths, so small exponents take log space too.
#define MOMENTS_ESM_LINEAR_EXPONENT 80.0f
#define MOMENTS_ESM_LINEAR_MIN_EXPONENT 1.0f

// Arguments of every moments_* kernel (passed by value). Depth `d` is light depth as rasterized;
// normalised depth is clamp((d - depthNear) * depthInvRange, 0, 1); NaN and +-INFINITY (background:
// nothing drawn) normalise to 1, the far end, i.e. "no occluder".
typedef struct MomentsParams {
  uint width, height;   // texels; the output has width*height texels per plane
  uint layerCount;      // LVSM: number of [p, q] layers (planes); otherwise 1
  uint esmLogSpace;     // ESM: 1 to store d (filtered in log space), 0 for e^(c (d - 1)) with c = expPositive
  float depthNear;      // light depth mapped to 0
  float depthInvRange;  // 1 / (depthFar - depthNear), finite and > 0
  float expPositive;    // EVSM c+ (already clamped on the host; the kernel clamps again); ESM's c
  float expNegative;    // EVSM c-
  // The window of the depth map the moments stage reads (kernels/moments.cl MOMENTS_DEPTH): width x height texels
  // from (originX, originY) of a map `pitch` texels wide; (0, 0) and width for the whole map.
  uint pitch, originX, originY, padEnd;
} MomentsParams;

#if PENUMBRA_HOST
static_assert(sizeof(MomentsParams) == 48, "MomentsParams layout is shared with OpenCL C");
static_assert(offsetof(MomentsParams, depthNear) == 16 && offsetof(MomentsParams, expNegative) == 28);
static_assert(offsetof(MomentsParams, esmLogSpace) == 12 && offsetof(MomentsParams, pitch) == 32);
#else

// Normalised depth in [0, 1]; every invalid depth is the far value 1 (handled before any warp, so NaN
// never reaches a filter).
inline float moments_normalize(float depth, float depthNear, float depthInvRange) {
  if (!isfinite(depth)) return 1.0f;
  float d = (depth - depthNear) * depthInvRange;
  return isnan(d) ? 1.0f : clamp(d, 0.0f, 1.0f);
}

// EVSM warps of normalised depth d: (e^(c+ x), -e^(-c- x)) with x = 2d - 1 in [-1, 1].
inline float2 moments_evsm_warp(float d, float expPositive, float expNegative) {
  float x = 2.0f * d - 1.0f;
  float cp = clamp(expPositive, 0.0f, MOMENTS_EVSM_MAX_EXPONENT_FP32);
  float cn = clamp(expNegative, 0.0f, MOMENTS_EVSM_MAX_EXPONENT_FP32);
  return (float2)(exp(cp * x), -exp(-cn * x));
}

// LVSM layer warp (Lauritzen & McCool eq. 6): 0 below p, 1 above q, linear between.
inline float moments_layer_warp(float d, float2 layer) {
  return clamp((d - layer.x) / (layer.y - layer.x), 0.0f, 1.0f);
}

// Log-space filtering of exponential shadow maps (Salvi, "Rendering filtered shadows with exponential shadow maps",
// ShaderX6, 2008): instead of e^(c d), the map holds the D with e^(c D) = the filtered e^(c d). Weighted taps d_k:
// D = m + ln(sum w_k e^(c (d_k - m))) / c around the largest tap m of weight > 0, so no exponential overflows whatever
// c, and the sum is at least that tap's weight. Two taps a and b blended by f (bilinear and trilinear lookups) are
// the case w = (1 - f, f). A c too small to resolve (below 1e-6) filters linearly, the formula's limit.
#define MOMENTS_LOG_MIN_EXPONENT 1e-6f
inline float moments_log_mix(float a, float b, float f, float c) {
  if (!(f > 0.0f)) return a;
  if (!(f < 1.0f)) return b;
  if (!(c > MOMENTS_LOG_MIN_EXPONENT)) return mix(a, b, f);
  const float m = fmax(a, b);
  return m + log((1.0f - f) * exp(c * (a - m)) + f * exp(c * (b - m))) / c;
}

// MSM: the four power moments of d through the optimized quantization transform (row vector times
// matrix, then +0.035955884801 on the first channel), so the moments survive 16-bit storage.
inline float4 moments_msm_encode(float d) {
  float d2 = d * d;
  float4 b = (float4)(d, d2, d2 * d, d2 * d2);
  float4 q;
  q.x = dot(b, (float4)(-2.07224649f, 32.23703778f, -68.571074599f, 39.3703274134f)) + 0.035955884801f;
  q.y = dot(b, (float4)(13.7948857237f, -59.4683975703f, 82.0359750338f, -35.364903257f));
  q.z = dot(b, (float4)(0.105877704f, -1.9077466311f, 9.3496555107f, -6.6543490743f));
  q.w = dot(b, (float4)(9.7924062118f, -33.7652110555f, 47.9456096605f, -23.9728048165f));
  return q;
}

// The moments of one depth texel in every single-plane encoding (unused channels 0): VSM (d, d^2), ESM d, EVSM2
// (w+, w+^2), EVSM4 (w+, w+^2, w-, w-^2), MSM the quantized four moments. The one definition of each
// encoding, shared by the moments kernels and the blur pass they can be fused into, so both agree bit for bit.
inline float4 moments_encode(float depth, MomentsParams p, int kind) {
  float d = moments_normalize(depth, p.depthNear, p.depthInvRange);
  if (kind == MOMENTS_KIND_MSM) return moments_msm_encode(d);
  if (kind == MOMENTS_KIND_VSM) return (float4)(d, d * d, 0.0f, 0.0f);
  if (kind == MOMENTS_KIND_ESM) return (float4)(p.esmLogSpace ? d : exp(p.expPositive * (d - 1.0f)), 0.0f, 0.0f, 0.0f);
  float2 w = moments_evsm_warp(d, p.expPositive, p.expNegative);
  if (kind == MOMENTS_KIND_EVSM2) return (float4)(w.x, w.x * w.x, 0.0f, 0.0f);
  return (float4)(w.x, w.x * w.x, w.y, w.y * w.y);
}

// Inverse of moments_msm_encode (filtered optimized moments back to power moments b1..b4).
inline float4 moments_msm_decode(float4 q) {
  q.x -= 0.035955884801f;
  float4 b;
  b.x = dot(q, (float4)(0.2227744146f, 0.0771972861f, 0.7926986636f, 0.0319417555f));
  b.y = dot(q, (float4)(0.1549679261f, 0.1394629426f, 0.7963415838f, -0.1722823173f));
  b.z = dot(q, (float4)(0.1451988946f, 0.2120202157f, 0.7258694464f, -0.2758014811f));
  b.w = dot(q, (float4)(0.163127443f, 0.2591432266f, 0.6539092497f, -0.3376131734f));
  return b;
}

#endif
#endif
