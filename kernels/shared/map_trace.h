// Beyond the papers: the lit share of a receiver by tracing its segments to MAP_TRACE_POINTS points of an area light
// through the light's depth map (a ray-traced shadow map, as screen-space ray marching does in a depth buffer; the
// points: 8 x 4 jittered cells, Shirley and Chiu's concentric map onto the disk). `vssm` and `pcss` call it where their
// blocker search finds blockers at several depths (stacked casters), whose single average depth, and VSSM's Chebyshev
// bound, let light into the umbra. OpenCL C only.
//
// The segment to the light point s (in the unit disk of the light) passes depth z at map position uv + s k, k = w(z)
// the light's footprint half-width at z in texels (lv_penumbra_texels), so it is marched in k from the receiver (k = 0)
// to the search kernel's edge (the nearest blocker's k), a texel of map position a step or at most MAP_TRACE_STEPS
// steps. It is blocked where it comes out from under the map's surface (from a depth beyond the texel's to one before
// it):
// - through the surface, where that is continuous (the texels' depths differ by no more than twice the segment's own
//   step in depth, or MAP_TRACE_SHEET of the depth range): it crossed a surface the light sees;
// - past a caster's outline (a depth discontinuity), where the deeper surface now seen lies between the depth at which
//   it went under and its own: what the nearer caster hides of a caster below it is taken to continue under it (stacked
//   plates). Else it passes, as past a thin caster's outline.
// Blockers at several depths fuse point by point. What it cannot see are the walls of a solid that face away from the
// light: a segment that goes under a solid's top and leaves through such a wall passes. So the callers keep the darker
// of this and their own lit share, and trace only where theirs leaves light.
#ifndef PENUMBRA_KERNELS_SHARED_MAP_TRACE_H
#define PENUMBRA_KERNELS_SHARED_MAP_TRACE_H

#include "kernels/shared/light_view.h"
#include "kernels/shared/rotation.h"
#include "kernels/shared/shadow_common.h"

#define MAP_TRACE_POINTS 32
#define MAP_TRACE_STEPS 16  // steps a segment at most: a texel of map position each, or more on wide kernels
#define MAP_TRACE_SHEET 0.05f

// The light depth at which the light's footprint from a receiver at depth d is k texels wide (lv_penumbra_texels
// inverted), from the receiver's texel width (lv_texel_world at d) and the light's size, which map_trace reads once.
inline float map_depth_at_footprint(bool spot, float d, float texel, float lightSize, float k) {
  return spot ? d / (1.0f + k * texel / lightSize) : d - k * texel / lightSize;
}

// The texel column (or row) holding map position q: floor(q) where q >= 0, else -1 (beyond the map, as floor's
// negative values are for sc_fetch); a truncating conversion, which equals floor there, costs less than floor.
inline int map_texel_of(float q) { return q >= 0.0f ? (int)q : -1; }

// The receiver at map position uv and light depth `depth` (world units), compared with the bias `bias` plus
// `biasSlope` per texel of offset, as a PCF tap; w: the search kernel's half-width in texels; seed: the pixel's.
inline float map_trace(__global const float* map, __constant const LightViewGpu* lv, float2 uv, float depth, float bias,
                       float biasSlope, float w, uint seed) {
  const int width = lv->width, height = lv->height;
  const float texel = lv_texel_world(lv, depth), lightSize = lv->lightSize;
  const bool spot = lv->kind == LIGHT_KIND_SPOT;
  const float zFar = map_depth_at_footprint(spot, depth, texel, lightSize, w);  // the search kernel's nearest blocker
  const float sheet = MAP_TRACE_SHEET * fmax(depth - zFar, 0.0f);
  // The receiver's own texel, where every segment starts (k = 0).
  const float m0 = sc_fetch(map, width, height, map_texel_of(uv.x), map_texel_of(uv.y)), f0 = depth - bias - m0;
  int lit = 0;
  for (int k = 0; k < MAP_TRACE_POINTS; ++k) {
    const uint tap = (seed * 4u * MAP_TRACE_POINTS + 2u * MAP_TRACE_POINTS + (uint)k) * 2u;
    const float a = 2.0f * (((float)(k % 8) + rot_hash01(tap)) / 8.0f) - 1.0f;
    const float b = 2.0f * (((float)(k / 8) + rot_hash01(tap + 1u)) / (float)(MAP_TRACE_POINTS / 8)) - 1.0f;
    // Shirley and Chiu's concentric map of the square [-1, 1]^2 onto the unit disk.
    float radius = 0.0f, phi = 0.0f;
    if (fabs(a) > fabs(b)) {
      radius = a, phi = (M_PI_F / 4.0f) * (b / a);
    } else if (b != 0.0f) {
      radius = b, phi = M_PI_F / 2.0f - (M_PI_F / 4.0f) * (a / b);
    }
    const float2 s = radius * (float2)(cos(phi), sin(phi));
    const float len = length(s);
    const int steps = min((int)ceil(w * len) + 1, MAP_TRACE_STEPS);
    const float dk = w / (float)steps;
    float prevZ = depth, prevM = m0, prevF = isfinite(f0) ? f0 : -1.0f, entered = depth;
    bool blocked = false;
    for (int i = 1; i <= steps && !blocked; ++i) {
      const float kk = dk * (float)i;
      const float2 q = uv + s * kk;
      const float z = map_depth_at_footprint(spot, depth, texel, lightSize, kk);
      const float mz = sc_fetch(map, width, height, map_texel_of(q.x), map_texel_of(q.y));
      const float tapBias = bias + biasSlope * kk * len;
      const float f = z - tapBias - mz;                           // > 0: the segment lies beyond the surface here
      if (!(prevF > 0.0f) && f > 0.0f) entered = prevZ;           // it passes under a caster's outline
      if (prevF > 0.0f && !(f > 0.0f))                            // out from under it: through it, or past it
        blocked = fabs(mz - prevM) <= fmax(2.0f * (prevZ - z), sheet) || (mz < entered - tapBias && mz > z);
      prevZ = z, prevM = mz, prevF = isfinite(f) ? f : -1.0f;
    }
    lit += !blocked;
  }
  return (float)lit / (float)MAP_TRACE_POINTS;
}

#endif
