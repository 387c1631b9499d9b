// Percentage-closer soft shadows (Fernando, "Percentage-Closer Soft Shadows", SIGGRAPH 2005 sketch):
// 1. blocker search over the region of the map the light disk subtends from the receiver, averaging the
//    depths of texels closer than the receiver; 2. penumbra width from similar triangles; 3. PCF over that
//    width. The brute-force baseline that VSSM must beat: cost grows with the search and filter tap counts.
// Taps (`pattern`, kernels/shared/shade.h): SHADE_PATTERN_GRID, a taps x taps grid over the square of the region's
// half-width; SHADE_PATTERN_POISSON, taps^2 points of a Poisson
// disk (Mitchell's best candidate, host side) over the region's disk, the shape the light disk actually gives both
// regions, rotated per pixel (kernels/shared/rotation.h) so the grid's banding becomes noise.
// Adaptive search (`adaptive`, beyond the sketch): a min-max pyramid of the map bounds the region first. Where no
// texel of the region's square lies in front of the receiver, nothing can block and the pixel is lit without a tap;
// otherwise the nearest caster in the region, z_min, replaces the near plane in the region's similar triangles (a
// blocker at depth z >= z_min occludes the light from the receiver only inside the light's cone cut at z, which
// narrows as z grows), twice, each time over the narrowed square: the taps stay on where blockers can be.
#include "kernels/shared/pyramid.h"
#include "kernels/shared/rotation.h"
#include "kernels/shared/shade.h"
#include "kernels/shared/shadow_common.h"

#define PCSS_ADAPTIVE_STEPS 2  // narrowings of the search region by the pyramid's nearest caster

// Tap k of a search or filter region of half-width `radius` texels: grid (taps x taps) or rotated Poisson disk.
inline float2 pcss_offset(int pattern, __global const float2* disk, float2 cs, int taps, int k, float radius) {
  if (pattern == SHADE_PATTERN_POISSON) return radius * rot_apply(cs, disk[k]);
  if (taps <= 1) return (float2)(0.0f);
  float step = 2.0f * radius / (float)(taps - 1);
  return (float2)(-radius + (k % taps) * step, -radius + (k / taps) * step);
}

// Average depth of blockers in the search region of half-width `radius` texels; returns 0 when no tap blocks.
inline float pcss_blocker_depth(__global const float* map, __constant const LightViewGpu* lv, Receiver r, float radius,
                                int pattern, __global const float2* disk, float2 cs, int taps) {
  float sum = 0.0f;
  int found = 0;
  for (int k = 0; k < taps * taps; ++k) {
    float2 offset = pcss_offset(pattern, disk, cs, taps, k, radius);
    float2 uv = r.uv + offset;
    float occluder = sc_fetch(map, lv->width, lv->height, (int)floor(uv.x), (int)floor(uv.y));
    float depth = r.depth - r.bias - r.biasSlope * length(offset);
    if (occluder < depth) {
      sum += occluder;
      ++found;
    }
  }
  return found > 0 ? sum / (float)found : 0.0f;
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
  float4 p = position[i];
  visibility[i] = 1.0f;
  blockerOut[i] = 0.0f;
  if (p.w == 0.0f) return;
  ShadowBias bias = {f.biasConstant, f.biasSlope, f.normalOffset};
  float3 n = normal[i].xyz;
  Receiver r = sc_receiver(lv, p.xyz, n, bias);
  if (!r.valid) return;
  float angle = rot_angle(i % width, i / width);
  float2 cs = (float2)(cos(angle), sin(angle));
  // The light disk seen from the receiver covers, at the near plane, the widest region that can hold blockers.
  float search = clamp(lv_penumbra_texels(lv, r.depth, lv->zNear), 0.5f, maxRadius);
  for (int step = 0; s.adaptive && step < PCSS_ADAPTIVE_STEPS; ++step) {
    // The square around the region's disk; texels beyond the map hold no caster.
    const float nearest = pyramid_depth_range_of(map, pyramid, levels, s.levelCount, lv->width, lv->height,
                                                 r.uv - search, r.uv + search, INFINITY)
                              .x;
    if (!(nearest < r.depth - r.bias)) {  // no tap can block (each compares against depth - bias or less)
      blockerOut[i] = -1.0f;
      return;
    }
    search = fmin(search, clamp(lv_penumbra_texels(lv, r.depth, fmax(nearest, lv->zNear)), 0.5f, maxRadius));
  }
  float blocker = pcss_blocker_depth(map, lv, r, search, pattern, searchDisk, cs, searchTaps);
  blockerOut[i] = blocker;
  if (blocker <= 0.0f) return;  // no blocker: fully lit
  float radius = clamp(lv_penumbra_texels(lv, r.depth, blocker), 0.5f, maxRadius);
  ReceiverPlane rp = sc_receiver_plane_at(f.receiverPlane, position, lv, width, height, i, p.xyz, n, r.texel);
  const float planeBias = f.biasConstant * r.texel;
  float sum = 0.0f;
  for (int k = 0; k < filterTaps * filterTaps; ++k)
    sum += sc_tap(map, lv, r, rp, planeBias, pcss_offset(pattern, filterDisk, cs, filterTaps, k, radius));
  visibility[i] = sum / (float)(filterTaps * filterTaps);
}
