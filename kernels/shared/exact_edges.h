// Exact shadow edges for hard shadow-map lookups (`--exact-edges`, beyond the papers; the hybrid of a shadow map and
// ray tracing that engines use against a map's aliasing, e.g. Story, "Hybrid ray-traced shadows", GDC 2015). A map
// decides a receiver from its nearest texel, so near a shadow edge, and everywhere on a caster thinner than a few
// texels, the texel and the receiver's own point may lie on opposite sides of the caster's outline: a wrong pixel at
// every edge crossing that no map resolution removes, only shrinks. The map also knows which triangle covers each
// texel (the rasterizer's triangle ids), so where the texels nearest the receiver's own map position disagree about it
// (biased depth tests against the receiver's plane), or agree with each other but not with the lookup, the receiver's
// shadow ray (the reference tracer's, kernels/shared/shadow_ray.h) is tested exactly against the triangles of the 3x3
// texels around that position and of the lookup's texel, then against their neighbours in the index buffer: one of
// them blocks it, or the receiver is lit. A 0 is always the reference's; a 1 is, unless the blocker is a triangle none
// of those holds (a caster no texel centre near the receiver samples). OpenCL C only.
#ifndef PENUMBRA_KERNELS_SHARED_EXACT_EDGES_H
#define PENUMBRA_KERNELS_SHARED_EXACT_EDGES_H

#include "kernels/shared/id_buffer.h"
#include "kernels/shared/shadow_common.h"
#include "kernels/shared/shadow_ray.h"

#define EXACT_EDGE_WINDOW 3      // texels a side around the receiver's own nearest texel
#define EXACT_EDGE_NEIGHBOURS 6  // triangles either side of a window's triangle in the index buffer also tested

// What the exact test reads: the scene's triangles, their alpha masks, and the scene radius (the ray offset's floor).
typedef struct {
  __global const float* positions;
  __global const uint* triangles;
  uint triangleCount;
  RayAlpha alpha;
  float sceneRadius;
} EdgeScene;

// The visibility of the receiver at world p on triangle `own` (shading normal n, the fallback of a degenerate one's
// geometric normal) whose map lookup at texel `looked` gave `lit`: -1 (the map decides) unless the texels nearest its
// own map position (the four around it, or with `wide` the 3x3 around its own texel) disagree about it, or agree with
// each other but not with the lookup; else 0 or 1 from its exact shadow ray against the triangles of the 3x3 texels
// around that position and of the looked-up texel (the normal offset moves the lookup off the window by up to a texel,
// and a caster thinner than a texel may show only there), then their neighbours. `map` and `ids` are lv's depth and
// triangle ids; the receiver's depth at texel centre c is z + g . (c - uv) (g the receiver plane's gradient where rp is
// valid, else 0) less `bias` (world units in light depth).
inline float edge_exact_lit(__global const float* map, __global const uint* ids, __constant const LightViewGpu* lv,
                            float3 p, uint own, float3 n, ReceiverPlane rp, float bias, float lit, int2 looked,
                            bool wide, const EdgeScene* s) {
  const float3 at = lv_project(lv, p);
  if (!(at.z > 0.0f) || !all(isfinite(at))) return -1.0f;
  const float2 g = rp.valid ? rp.gradient : (float2)(0.0f);
  const int side = EXACT_EDGE_WINDOW, all = side * side;
  const int x0 = (int)floor(at.x) - side / 2, y0 = (int)floor(at.y) - side / 2;
  // Detection: the 3x3 from (x0, y0), or the four around the position from its lower-left nearest centre.
  const int detect = wide ? side : 2, dx = wide ? x0 : (int)floor(at.x - 0.5f),
            dy = wide ? y0 : (int)floor(at.y - 0.5f);
  int blocked = 0;
  for (int k = 0; k < detect * detect; ++k) {
    const int x = dx + k % detect, y = dy + k / detect;
    const float2 c = (float2)((float)x + 0.5f, (float)y + 0.5f) - at.xy;
    blocked += sc_lit(sc_fetch(map, lv->width, lv->height, x, y), at.z - bias + dot(g, c)) == 0.0f;
  }
  if ((blocked == 0 && lit == 1.0f) || (blocked == detect * detect && lit == 0.0f)) return -1.0f;
  const float3 n0 = ray_geometric_normal(s->positions, s->triangles, own, n);
  const ShadowRay ray = ray_towards_light(p, n0, lv, s->sceneRadius);
  uint tested[EXACT_EDGE_WINDOW * EXACT_EDGE_WINDOW + 1];
  int count = 0;
  for (int k = -1; k < all; ++k) {  // -1: the looked-up texel
    const int x = k < 0 ? looked.x : x0 + k % side, y = k < 0 ? looked.y : y0 + k / side;
    if (x < 0 || y < 0 || x >= lv->width || y >= lv->height) continue;
    const uint t = ids[y * lv->width + x];
    bool seen = t == ID_NONE;
    for (int j = 0; j < count && !seen; ++j) seen = tested[j] == t;
    if (seen) continue;
    tested[count++] = t;
    if (ray_blocked_by(&ray, t, s->positions, s->triangles, &s->alpha)) return 0.0f;
  }
  // None of them: their neighbours in the index buffer, where a caster thinner than a texel keeps the triangles the
  // texels missed (a quad's other half, a strip's next, a thin box's other faces).
  for (int j = 0; j < count; ++j)
    for (int d = -EXACT_EDGE_NEIGHBOURS; d <= EXACT_EDGE_NEIGHBOURS; ++d) {
      if (d == 0 || (d < 0 && tested[j] < (uint)(-d))) continue;
      const uint t = tested[j] + (uint)d;  // wraps to tested[j] - |d| for d < 0
      if (t >= s->triangleCount) continue;
      if (ray_blocked_by(&ray, t, s->positions, s->triangles, &s->alpha)) return 0.0f;
    }
  return 1.0f;
}

#endif
