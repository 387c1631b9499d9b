// Percentage-closer soft shadows (Fernando, "Percentage-Closer Soft Shadows", SIGGRAPH 2005 sketch):
// 1. blocker search over the region of the map the light disk subtends from the receiver, averaging the
//    depths of texels closer than the receiver; 2. penumbra width from similar triangles; 3. PCF over that
//    width. The brute-force baseline that VSSM must beat: cost grows with the search and filter tap counts.
// Taps (`pattern`, kernels/shared/shade.h): SHADE_PATTERN_GRID, a taps x taps grid over the square of the region's
// half-width; SHADE_PATTERN_POISSON, the first taps^2 (or, under auto, as many as the region needs) points of a
// progressive Poisson disk (Mitchell's best candidate in the order it places them, host side: every prefix is spread
// over the whole disk) over the region's disk, the shape the light disk actually gives both regions, rotated per pixel
// (kernels/shared/rotation.h) so the grid's banding becomes noise.
// Adaptive search (`adaptive`, beyond the sketch): a min-max pyramid of the map bounds the region first. Where no
// texel of the region's square lies in front of the receiver, nothing can block and the pixel is lit without a tap;
// otherwise the nearest caster in the region, z_min, replaces the near plane in the region's similar triangles (a
// blocker at depth z >= z_min occludes the light from the receiver only inside the light's cone cut at z, which
// narrows as z grows), twice, each time over the narrowed square: the taps stay on where blockers can be.
// Umbra (`umbra`, with the pyramid): where every search tap blocked, the pyramid's farthest texel under the filter's
// square decides whether every filter tap must read 0; then the pixel is 0 without the filter's taps.
#include "kernels/shared/map_trace.h"
#include "kernels/shared/pyramid.h"
#include "kernels/shared/rotation.h"
#include "kernels/shared/shade.h"
#include "kernels/shared/shadow_common.h"

#define PCSS_ADAPTIVE_STEPS 2  // narrowings of the search region by the pyramid's nearest caster
#define PCSS_STACKED_SPREAD 0.1f  // blockers at several depths: the average this share of the way past the nearest

// The taps a region of half-width `radius` texels gets, and in *side the grid's taps per side: fixed, taps x taps;
// automatic, from the region's texels (PCSS_*_DENSITY, kernels/shared/shade.h) within [fewest, taps^2] (the grid: the
// side of a square of that many). A disk's automatic count is real: its whole part are full taps and the next tap
// weighs the fraction (pcss_tap_weight), so that the estimate moves continuously with the radius instead of jumping as
// a tap is added.
inline float pcss_tap_count(int automatic, int taps, float density, int fewest, float radius, int pattern, int* side) {
  *side = taps;
  if (!automatic) return (float)(taps * taps);
  const float wanted = density * M_PI_F * radius * radius;
  const int most = taps * taps;
  if (pattern == SHADE_PATTERN_POISSON) return clamp(wanted, (float)min(fewest, most), (float)most);
  *side = (int)clamp(ceil(sqrt(wanted)), (float)min((int)ceil(sqrt((float)fewest)), taps), (float)taps);
  return (float)(*side * *side);
}

// Tap k's weight among `count` (pcss_tap_count): 1, the last of a fractional count its fraction.
inline float pcss_tap_weight(int k, float count) { return fmin(count - (float)k, 1.0f); }

// Tap k of a search or filter region of half-width `radius` texels: grid (taps x taps) or rotated Poisson disk.
inline float2 pcss_offset(int pattern, __global const float2* disk, float2 cs, int taps, int k, float radius) {
  if (pattern == SHADE_PATTERN_POISSON) return radius * rot_apply(cs, disk[k]);
  if (taps <= 1) return (float2)(0.0f);
  float step = 2.0f * radius / (float)(taps - 1);
  return (float2)(-radius + (k % taps) * step, -radius + (k / taps) * step);
}

// Average depth of blockers in the search region of half-width `radius` texels over `count` taps (`taps` per side on
// the grid; pcss_tap_weight); returns 0 when no tap blocks. *nearest: the nearest blocking tap's depth.
inline float pcss_blocker_depth(__global const float* map, __constant const LightViewGpu* lv, Receiver r, float radius,
                                int pattern, __global const float2* disk, float2 cs, int taps, float count, int* every,
                                float* nearest) {
  float sum = 0.0f, found = 0.0f;
  *nearest = INFINITY;
  int all = 1;
  for (int k = 0; (float)k < count; ++k) {
    float2 offset = pcss_offset(pattern, disk, cs, taps, k, radius);
    float2 uv = r.uv + offset;
    float occluder = sc_fetch(map, lv->width, lv->height, (int)pn_floor(uv.x), (int)pn_floor(uv.y));
    float depth = r.depth - r.bias - r.biasSlope * length(offset);
    if (occluder < depth) {
      const float weight = pcss_tap_weight(k, count);
      sum += weight * occluder;
      found += weight;
      *nearest = fmin(*nearest, occluder);
    } else {
      all = 0;
    }
  }
  *every = all;
  return found > 0.0f ? sum / found : 0.0f;
}

__kernel void pcss_visibility(__global const float4* position, __global const float4* normal, __global const float* map,
                              __constant const LightViewGpu* lv, ShadeFrame f, PcssShade s,
                              __global const float2* searchDisk, __global const float2* filterDisk,
                              __global const float2* pyramid, __constant const PyramidLevel* levels,
                              __global float* blockerOut, __global float* visibility) {
  const uint width = f.width, height = f.height;
  const int searchTaps = s.searchTaps, filterTaps = s.filterTaps, pattern = s.pattern;
  const float maxRadius = s.maxRadius;
  uint i = get_global_id(0);
  if (i >= width * height) return;
  if (s.adaptive)
    pyramid_prefetch_ahead(position, lv, map, pyramid, levels, s.levelCount, i + PN_PREFETCH_AHEAD, width * height);
  float4 p = position[i];
  visibility[i] = 1.0f;
  blockerOut[i] = 0.0f;
  if (p.w == 0.0f) return;
  ShadowBias bias = {f.biasConstant, f.biasSlope, f.normalOffset};
  float3 n = normal[i].xyz;
  // The receiver without its slope-scaled bias first (sc_receiver_unsloped: two projections, not six): its bias is at
  // least texel * base, so a region whose nearest texel lies behind depth - texel * base lets every tap through under
  // the full bias too, and most lit pixels leave below without the slope (default.json at 640x360: 74 k of 89 k).
  Receiver r = sc_receiver_unsloped(lv, p.xyz, n, bias);
  if (!r.valid) return;
  int sloped = 0;
  // The light disk seen from the receiver covers, at the near plane, the widest region that can hold blockers.
  float search = clamp(lv_penumbra_texels(lv, r.depth, lv->zNear), 0.5f, maxRadius);
  for (int step = 0; s.adaptive; ++step) {
    // The square around the region's disk; texels beyond the map hold no caster.
    const float nearest = pyramid_depth_range_of(map, pyramid, levels, s.levelCount, lv->width, lv->height,
                                                 r.uv - search, r.uv + search, INFINITY)
                              .x;
    // No tap can block: each compares against depth - bias or less (bias >= texel * base, so an unsloped receiver
    // whose region passes depth - texel * base is lit without its slope).
    if (!sloped && nearest < r.depth - r.texel * bias.base) r = sc_receiver_sloped(lv, r, p.xyz, n, bias), sloped = 1;
    if (!sloped || !(nearest < r.depth - r.bias)) {
      blockerOut[i] = -1.0f;
      return;
    }
    if (step == PCSS_ADAPTIVE_STEPS) break;  // the last narrowed region tested too
    const float narrowed = clamp(lv_penumbra_texels(lv, r.depth, fmax(nearest, lv->zNear)), 0.5f, maxRadius);
    if (!(narrowed < search)) break;
    search = narrowed;
  }
  if (!sloped) r = sc_receiver_sloped(lv, r, p.xyz, n, bias);
  // The pattern's rotation, once the pyramid has not let the pixel go (most lit pixels leave above without it).
  const float angle = rot_angle(i % width, i / width);
  const float2 cs = (float2)(cos(angle), sin(angle));
  int searchSide;
  const float searchCount = pcss_tap_count(s.autoTaps & PCSS_AUTO_SEARCH, searchTaps, PCSS_SEARCH_DENSITY,
                                         PCSS_SEARCH_FEWEST, search, pattern, &searchSide);
  int every;
  float nearest;
  float blocker =
      pcss_blocker_depth(map, lv, r, search, pattern, searchDisk, cs, searchSide, searchCount, &every, &nearest);
  blockerOut[i] = blocker;
  if (blocker <= 0.0f) return;  // no blocker: fully lit
  float radius = clamp(lv_penumbra_texels(lv, r.depth, blocker), 0.5f, maxRadius);
  if (every && s.umbra && s.adaptive) {
    // Likely umbra (every search tap blocked): the pyramid tells for sure. Every texel a filter tap reads lies within
    // `reach` of the receiver and in front of the strictest comparison a tap makes there (the receiver's plane no
    // steeper than SHADOW_MAX_SLOPE, or the slope-scaled bias at the square's corner): every filter tap reads 0, so
    // the filter's sum is 0, bit for bit, without its taps or the receiver's plane.
    const float reach = radius * (pattern == SHADE_PATTERN_POISSON ? 1.0f : M_SQRT2_F) + 1.5f;
    const float far = pyramid_depth_range_of(map, pyramid, levels, s.levelCount, lv->width, lv->height, r.uv - reach,
                                             r.uv + reach, INFINITY)
                          .y;
    const float slack = M_SQRT2_F * reach;
    const float strictest = fmin(r.depth - f.biasConstant * r.texel - SHADOW_MAX_SLOPE * r.texel * slack,
                                 r.depth - r.bias - r.biasSlope * slack);
    if (far < strictest - 1e-5f * fabs(r.depth)) {
      visibility[i] = 0.0f;
      return;
    }
  }
  ReceiverPlane rp = sc_receiver_plane_at(f.receiverPlane, position, lv, width, height, i, p.xyz, n, r.texel);
  const float planeBias = f.biasConstant * r.texel;
  if (every && s.umbra && s.adaptive) {
    // The same question again, closer, now that the filter needs the receiver's plane anyway: the texels a tap reads
    // (bilinear: within 1.5 texels of its point a side) lie within `reach` of the receiver, every comparison is at
    // least as strict as the plane's lowest point on that disk (or the slope-scaled bias at its rim), and the pyramid's
    // farthest texel on the disk (pyramid_far_in_disk: no square's corners, a finer level) must lie in front of it.
    // default.json at 640x360: of the 4.9 k pixels whose every search tap blocked and which the square left to the
    // taps, this settles 3.0 k.
    const float reach = radius * (pattern == SHADE_PATTERN_POISSON ? 1.0f : M_SQRT2_F) + 1.5f * M_SQRT2_F + 0.1f;
    const float fall = rp.valid ? length(rp.gradient) * reach : r.biasSlope * reach;
    const float strictest = (rp.valid ? r.depth - planeBias : r.depth - r.bias) - fall;
    const float far =
        pyramid_far_in_disk(map, pyramid, levels, s.levelCount, lv->width, lv->height, r.uv, reach, INFINITY);
    if (far < strictest - 1e-5f * (fabs(r.depth) + fall)) {
      visibility[i] = 0.0f;
      return;
    }
  }
  int filterSide;
  const float filterCount = pcss_tap_count(s.autoTaps & PCSS_AUTO_FILTER, filterTaps, PCSS_FILTER_DENSITY,
                                           PCSS_FILTER_FEWEST, radius, pattern, &filterSide);
  const int sparse =
      s.sparseTaps && sc_sparse_taps(filterCount, (pattern == SHADE_PATTERN_POISSON ? M_PI_F : 4.0f) * radius * radius);
  float sum = 0.0f;
  if (sparse) {
    for (int k = 0; (float)k < filterCount; ++k)
      sum += pcss_tap_weight(k, filterCount) *
             sc_tap_texel(map, lv, r, rp, planeBias, pcss_offset(pattern, filterDisk, cs, filterSide, k, radius));
  } else {
    for (int k = 0; (float)k < filterCount; ++k)
      sum += pcss_tap_weight(k, filterCount) *
             sc_tap(map, lv, r, rp, planeBias, pcss_offset(pattern, filterDisk, cs, filterSide, k, radius));
  }
  float lit = sum / filterCount;
  // Beyond the paper: blockers at several depths (the average more than PCSS_STACKED_SPREAD of the way from the nearest
  // to the receiver, vssm's --vssm-stacked test) size the filter from a depth between them, which lets light into the
  // umbra of the lower ones; their segments are traced as well where the filter leaves light, and the darker kept.
  if (s.stackedTrace && lit > 0.0f && blocker - nearest > PCSS_STACKED_SPREAD * (r.depth - nearest))
    lit = fmin(lit, map_trace(map, lv, r.uv, r.depth, r.bias, r.biasSlope, search, i));
  visibility[i] = lit;
}
