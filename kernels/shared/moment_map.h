// Shading side of the moment shadow maps (vsm, evsm2/4, esm, msm, savsm): the parameters every moment
// visibility kernel takes, the receiver in normalised depth, the filter footprint from neighbouring G-buffer
// pixels (OpenCL has no ddx/ddy), and bilinear / trilinear lookups of 2- or 4-channel moment textures with
// clamp-to-edge (the blur stage's edge rule). Shared by host and kernels.
#ifndef PENUMBRA_KERNELS_SHARED_MOMENT_MAP_H
#define PENUMBRA_KERNELS_SHARED_MOMENT_MAP_H

#include "kernels/shared/common.h"
#include "kernels/shared/moments.h"
#include "kernels/shared/pyramid.h"
#include "kernels/shared/storage.h"

#define MOMENT_WIDTH_FIXED 0      // savsm: filter width = filterWidth texels
#define MOMENT_WIDTH_LIGHT 1      // savsm: penumbra of an occluder occluderDistance in front of the receiver
#define MOMENT_WIDTH_FOOTPRINT 2  // savsm: the pixel's footprint in the map

// Arguments of every moment visibility kernel (passed by value).
typedef struct MomentShade {
  uint width, height;              // G-buffer pixels (row 0 at the bottom)
  uint channels;                   // floats per moment texel: 2 or 4
  uint levels;                     // moment mip levels including the base; 1 = bilinear lookups only
  float depthNear, depthInvRange;  // the moments stage's normalisation (kernels/shared/moments.h)
  float bias, slopeBias;           // ShadowBias: texel footprints at the receiver
  float normalOffset;
  float minVariance;       // Chebyshev variance clamp, normalised depth^2
  float bleeding;          // light-bleeding reduction amount (linstep), 0 = off
  float expPositive;       // EVSM c+ / ESM c, already clamped to the storage
  float expNegative;       // EVSM c-
  float momentBias;        // MSM alpha
  uint widthMode;          // savsm: MOMENT_WIDTH_*
  float filterWidth;       // savsm: fixed width, and the smallest width of the other modes (texels)
  float maxWidth;          // savsm: largest filter width (texels)
  float occluderDistance;  // savsm, light mode: typical occluder-receiver distance (world units)
  float blurSigma;         // standard deviation of the moment blur in texels (0: none)
  float filterBias;        // receiver-plane bias in standard deviations of the filter footprint
  uint esmLogSpace;        // esm: the map holds depths filtered in log space (1) or e^(c (d - 1)) (0)
} MomentShade;

#if PENUMBRA_HOST
static_assert(sizeof(MomentShade) == 84, "MomentShade layout is shared with OpenCL C");
static_assert(offsetof(MomentShade, depthNear) == 16 && offsetof(MomentShade, widthMode) == 56);
#else
#include "kernels/shared/shadow_common.h"

// A receiver ready for a moment lookup.
typedef struct MomentReceiver {
  float2 uv;        // continuous texel coordinates in the base level
  float t;          // biased receiver depth, normalised like the moments, at most 1 (background)
  float tSlope;     // normalised depth change of the receiver's plane per texel of filter offset
  float depth;      // linear light depth of the receiver (world units)
  float footprint;  // the pixel's size in base texels (0 when no neighbour qualifies)
  int valid;        // 0: background, behind the light or outside the map -> fully lit
} MomentReceiver;

// Receiver set-up: normal offset and depth bias as for sm/pcf (sc_receiver), depth normalised like the
// moments. Points outside the map are lit: nothing beyond the fitted frustum casts shadows.
inline MomentReceiver mm_receiver(__global const float4* position, __global const float4* normal,
                                  __constant const LightViewGpu* lv, MomentShade s, uint i) {
  MomentReceiver m;
  m.valid = 0;
  m.footprint = 0.0f;
  float4 p = position[i];
  if (p.w == 0.0f) return m;
  float3 n = normal[i].xyz;
  ShadowBias bias = {s.bias, s.slopeBias, s.normalOffset};
  Receiver r = sc_receiver(lv, p.xyz, n, bias);
  m.uv = r.uv;
  m.depth = r.depth;
  // Not clamped below: the bias may take t under the nearest occluder, and must keep it there.
  m.t = clamp((r.depth - r.bias - s.depthNear) * s.depthInvRange, -1.0f, 1.0f);
  m.tSlope = r.biasSlope * s.depthInvRange;
  m.valid = r.valid && r.uv.x >= 0.0f && r.uv.y >= 0.0f && r.uv.x <= (float)lv->width && r.uv.y <= (float)lv->height &&
            isfinite(m.t);
  // Read only by a mip chain's level (mm_lod: bilinear lookups alone, levels 1, never) and savsm's footprint width:
  // its neighbours' reads and projections are left out elsewhere (vsm's default: 14 % of its shading).
  if (m.valid && (s.levels > 1 || s.widthMode == MOMENT_WIDTH_FOOTPRINT))
    m.footprint = sc_footprint_texels(sc_footprint(position, lv, s.width, s.height, i, p.xyz, n));
  return m;
}

// Moment images are fp32, or half when the kernel is built with -DSTORE_HALF (kernels/shared/storage.h).
#define MomentScalar PN_SCALAR

// The base level's texels under the pixel PN_PREFETCH_AHEAD work-items after pixel i, asked of the caches on CPU
// devices (sc_prefetch_texels): its bilinear lookup's two rows.
inline void mm_prefetch(__global const float4* position, __constant const LightViewGpu* lv,
                        __global const MomentScalar* base, MomentShade s, uint i) {
  sc_prefetch_texels(position, lv, base, s.channels * (uint)sizeof(MomentScalar), 1, i + PN_PREFETCH_AHEAD,
                     s.width * s.height);
}

// One moment texel (unused channels 0), clamped to the level's edge.
inline float4 mm_fetch(__global const MomentScalar* data, uint channels, PyramidLevel l, int x, int y) {
  x = clamp(x, 0, (int)l.width - 1);
  y = clamp(y, 0, (int)l.height - 1);
  size_t texel = (size_t)l.offset + (size_t)y * l.width + (size_t)x;
  if (channels == 1) return (float4)(PN_VLOAD(1, texel, data), 0.0f, 0.0f, 0.0f);
  return channels == 4 ? PN_VLOAD(4, texel, data) : (float4)(PN_VLOAD(2, texel, data), 0.0f, 0.0f);
}

// Bilinear lookup at continuous texel coordinates `uv` of level `l` (texel centres at +0.5).
inline float4 mm_bilinear(__global const MomentScalar* data, uint channels, PyramidLevel l, float2 uv) {
  float2 t = uv - 0.5f;
  float2 base = pn_floor2(t);
  float2 f = t - base;
  int x = (int)base.x, y = (int)base.y;
  float4 bottom = mix(mm_fetch(data, channels, l, x, y), mm_fetch(data, channels, l, x + 1, y), f.x);
  float4 top = mix(mm_fetch(data, channels, l, x, y + 1), mm_fetch(data, channels, l, x + 1, y + 1), f.x);
  return mix(bottom, top, f.y);
}

// mm_bilinear of ESM's log-space depths (one channel, kernels/shared/moments.h moments_log_mix with exponent c).
inline float mm_bilinear_log(__global const MomentScalar* data, PyramidLevel l, float2 uv, float c) {
  float2 t = uv - 0.5f;
  float2 base = pn_floor2(t);
  float2 f = t - base;
  int x = (int)base.x, y = (int)base.y;
  float bottom = moments_log_mix(mm_fetch(data, 1, l, x, y).x, mm_fetch(data, 1, l, x + 1, y).x, f.x, c);
  float top = moments_log_mix(mm_fetch(data, 1, l, x, y + 1).x, mm_fetch(data, 1, l, x + 1, y + 1).x, f.x, c);
  return moments_log_mix(bottom, top, f.y, c);
}

// Level `k` of the chain: the base buffer for 0, `mips` (levels 1..) otherwise.
inline PyramidLevel mm_level(__constant const LightViewGpu* lv, __constant const PyramidLevel* mipLevels, int k) {
  if (k == 0) {
    PyramidLevel base = {0u, (uint)lv->width, (uint)lv->height, 0u};
    return base;
  }
  return mipLevels[k - 1];
}

// Trilinear lookup (isotropic, Williams 1983): level log2(footprint) between its two nearest levels, with uv
// scaled to each level's size. Footprints up to one texel read the base level bilinearly.
inline float mm_lod(MomentShade s, float footprint) {
  return s.levels > 1 && footprint > 1.0f ? min(log2(footprint), (float)(s.levels - 1)) : 0.0f;
}

// uv in the texels of level l.
inline float2 mm_level_uv(__constant const LightViewGpu* lv, PyramidLevel l, float2 uv) {
  return uv * (float2)((float)l.width / (float)lv->width, (float)l.height / (float)lv->height);
}

inline float4 mm_sample(__global const MomentScalar* base, __global const MomentScalar* mips,
                        __constant const PyramidLevel* mipLevels, __constant const LightViewGpu* lv, MomentShade s,
                        float2 uv, float footprint) {
  float lod = mm_lod(s, footprint);
  int k = min((int)lod, (int)s.levels - 1);
  float f = lod - (float)k;
  PyramidLevel l0 = mm_level(lv, mipLevels, k);
  float4 m = mm_bilinear(k == 0 ? base : mips, s.channels, l0, mm_level_uv(lv, l0, uv));
  if (f <= 0.0f || k + 1 >= (int)s.levels) return m;
  PyramidLevel l1 = mm_level(lv, mipLevels, k + 1);
  return mix(m, mm_bilinear(mips, s.channels, l1, mm_level_uv(lv, l1, uv)), f);
}

// mm_sample of ESM's log-space depths: the levels' bilinear lookups and their blend in log space.
inline float mm_sample_log(__global const MomentScalar* base, __global const MomentScalar* mips,
                           __constant const PyramidLevel* mipLevels, __constant const LightViewGpu* lv, MomentShade s,
                           float2 uv, float footprint, float c) {
  float lod = mm_lod(s, footprint);
  int k = min((int)lod, (int)s.levels - 1);
  float f = lod - (float)k;
  PyramidLevel l0 = mm_level(lv, mipLevels, k);
  float d = mm_bilinear_log(k == 0 ? base : mips, l0, mm_level_uv(lv, l0, uv), c);
  if (f <= 0.0f || k + 1 >= (int)s.levels) return d;
  PyramidLevel l1 = mm_level(lv, mipLevels, k + 1);
  return moments_log_mix(d, mm_bilinear_log(mips, l1, mm_level_uv(lv, l1, uv), c), f, c);
}

// The receiver-plane bias of a filtered lookup: over a filter footprint whose offsets have standard
// deviation `sigma` texels, a tilted receiver's own depth spreads by tSlope * sigma around t. PCF adds the
// same slope per texel of tap offset (kernels/pcf.cl); here `filterBias` standard deviations keep a planar
// receiver in front of its own filtered depths. MSM needs this: its bound at t = mean is not 0 (about 0.1
// for a uniform spread, 0 from about one standard deviation in front); it also absorbs clamp-to-edge
// errors of coarse mip levels at the map's border.
inline float mm_filtered_t(MomentReceiver r, MomentShade s, float sigma) {
  return r.t - s.filterBias * r.tSlope * sigma;
}

// The filter width (texels) of receiver `r`'s lookup, and r->t moved in front of the receiver's own spread over the
// blur and mip footprint.
inline void mm_lookup_footprint(MomentShade s, MomentReceiver* r, float* width) {
  float lod = mm_lod(s, r->footprint);
  float size = exp2(floor(lod)), f = lod - floor(lod);
  *width = size * (1.0f + f);
  // Variances add: the blur, then a level-k texel (a box of 2^k base texels: 2^2k / 12) read through the
  // bilinear tent (2^2k / 6), blended with level k+1 (twice the size) by the fraction f.
  float sigma = sqrt(s.blurSigma * s.blurSigma + 0.25f * size * size * (1.0f + 3.0f * f));
  r->t = mm_filtered_t(*r, s, sigma);
}

// Lookup for receiver `r` with the technique's sampling (mm_lookup_footprint, then mm_sample).
inline float4 mm_lookup(__global const MomentScalar* base, __global const MomentScalar* mips,
                        __constant const PyramidLevel* mipLevels, __constant const LightViewGpu* lv, MomentShade s,
                        MomentReceiver* r, float* width) {
  mm_lookup_footprint(s, r, width);
  return mm_sample(base, mips, mipLevels, lv, s, r->uv, r->footprint);
}

// mm_lookup of ESM's log-space depths (exponent c): the filtered D of e^(c D).
inline float mm_lookup_log(__global const MomentScalar* base, __global const MomentScalar* mips,
                           __constant const PyramidLevel* mipLevels, __constant const LightViewGpu* lv, MomentShade s,
                           MomentReceiver* r, float* width, float c) {
  mm_lookup_footprint(s, r, width);
  return mm_sample_log(base, mips, mipLevels, lv, s, r->uv, r->footprint, c);
}

// Per-pixel outputs: visibility and the debug layers (filtered moments; variance and filter width).
inline void mm_store(uint i, float lit, float4 moments, float variance, float width, __global float* visibility,
                     __global float4* debugMoments, __global float2* debugStats) {
  visibility[i] = isnan(lit) ? 1.0f : clamp(lit, 0.0f, 1.0f);
  debugMoments[i] = moments;
  debugStats[i] = (float2)(variance, width);
}

#endif
#endif
