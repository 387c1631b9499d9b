// Receiver set-up and depth comparison shared by the shadow-map techniques (sm, pcf, pcss, and the moment
// family's receivers): normal offset, constant and slope-scaled bias in units of the local texel footprint
// (so defaults work at any scene scale), the pixel's footprint in the map from neighbouring G-buffer pixels
// (OpenCL has no ddx/ddy), receiver-plane depth bias, and bilinear-weighted depth comparisons. OpenCL C only.
#ifndef PENUMBRA_KERNELS_SHARED_SHADOW_COMMON_H
#define PENUMBRA_KERNELS_SHARED_SHADOW_COMMON_H

#include "kernels/shared/light_view.h"

// Biases in texel footprints (world width of one shadow-map texel at the receiver: per light depth for uniform maps,
// the warped texel's longer side at the receiver for LiSPSM maps, lv_texel_world_at).
typedef struct ShadowBias {
  float base;          // added to every comparison
  float slope;         // times the receiver's depth slope in the map (sc_depth_slope), clamped
  float normalOffset;  // receiver moved along its geometric normal before projection (SHADOW_NORMAL_OFFSET_SCALED)
} ShadowBias;

#define SHADOW_MAX_SLOPE 10.0f  // tan of ~84 degrees: beyond this the surface is nearly edge-on

// The normal offset scaled by sin(theta), theta the angle between the normal and the light (1, the default), or the
// whole offset at every angle (0: sm, fvsm and jittered, whose one nearest-texel comparison per pass has no filter
// and whose tests and tables were measured that way). Moving the receiver d along its normal puts it d / cos(theta)
// in front of its own plane along the light ray, the margin grazing receivers need, but also d sin(theta) sideways
// in the map and closer to its blockers: every shadow edge shifts, and pcss's and vssm's penumbrae come out narrower.
// Scaled, the margin is d tan(theta), the slope-scaled bias's growth, and a receiver facing the light is not moved.
// Measured in docs/techniques/README.md ("The normal offset and the depth slope").
#ifndef SHADOW_NORMAL_OFFSET_SCALED
#define SHADOW_NORMAL_OFFSET_SCALED 1
#endif

// A receiver projected into the map: texel coordinates, its light depth and the bias per texel of
// filter offset (grows with the filter footprint so tilted planar receivers do not self-shadow).
typedef struct Receiver {
  float2 uv;       // continuous texel coordinates (row 0 at the bottom)
  float depth;     // linear light depth of the receiver
  float bias;      // depth bias at the centre tap
  float biasSlope; // extra bias per texel of tap offset
  float texel;     // world width of one texel at the receiver
  int valid;       // 0 when the point is behind the light or not a surface
} Receiver;

// The receiver plane's light-depth change per texel of map offset, in texel footprints (world depth per texel /
// texel width), at most SHADOW_MAX_SLOPE: the slope the slope-scaled bias and the bias cone of filter taps scale by.
// Measured by projecting two tangent steps of one footprint, so it is exact to first order for every projection. For
// a uniform directional map, and on a spot map's axis, it is tan(theta), theta the angle between the normal and the
// light; off a spot map's axis the linear light depth (eye z, not the distance along the ray) of a plane changes
// faster than tan(theta) says: a ground point 30 degrees off the axis of a spot 2 above it, the ray 30 degrees from
// the normal, has 0.86 against tan(theta) = 0.59, and a cone of tan(theta) lets the far taps of a large kernel (pcss's
// search, vssm's sub-kernels) shadow their own receiver.
inline float sc_depth_slope(__constant const LightViewGpu* lv, float3 position, float3 normal, float texel) {
  float3 t1 = normalize(cross(normal, fabs(normal.x) < 0.9f ? (float3)(1.0f, 0.0f, 0.0f) : (float3)(0.0f, 1.0f, 0.0f)));
  float3 t2 = cross(normal, t1);
  // Central differences: a perspective map's depth is not linear along the plane, and one-sided steps of a
  // footprint were off by about texel / depth (1 % under a wide spot).
  t1 *= 0.5f * texel, t2 *= 0.5f * texel;
  float3 a = lv_project(lv, position + t1) - lv_project(lv, position - t1);
  float3 b = lv_project(lv, position + t2) - lv_project(lv, position - t2);
  // J = [a.xy b.xy] takes tangent steps to texel offsets, (a.z, b.z) their depth steps: g = J^-T (a.z, b.z).
  float det = a.x * b.y - b.x * a.y;
  float2 g = (float2)(b.y * a.z - a.y * b.z, a.x * b.z - b.x * a.z) / det;
  float slope = length(g) / texel;
  return isfinite(slope) ? min(slope, SHADOW_MAX_SLOPE) : SHADOW_MAX_SLOPE;
}

// sc_receiver without its depth slope: bias and biasSlope are left 0 for sc_receiver_sloped to fill in. The hard tests
// (sm, fvsm, jittered) compare against the receiver's plane wherever it is known and need the slope-scaled bias only
// where it is not: the slope's four projections are then skipped (default.json at 640x360, alternated A/B runs:
// sm_visibility 7.3 -> 5.5 ms, fvsm_visibility 8.4 -> 6.2 ms, the same images bit for bit); pcf's taps likewise.
inline Receiver sc_receiver_unsloped(__constant const LightViewGpu* lv, float3 position, float3 normal,
                                     ShadowBias bias) {
  Receiver r;
  float3 toLight = lv_to_light(lv, position);
  float cosTheta = dot(normal, toLight);
  if (cosTheta < 0.0f) {  // back-facing to the light: compare with the flipped normal (thin, two-sided)
    normal = -normal;
    cosTheta = -cosTheta;
  }
  float3 first = lv_project(lv, position);
  float texel = lv_texel_world_at(lv, position, max(first.z, lv->zNear));
  float offset = SHADOW_NORMAL_OFFSET_SCALED ? sqrt(max(1.0f - cosTheta * cosTheta, 0.0f)) : 1.0f;
  float3 moved = position + normal * (bias.normalOffset * offset * texel);
  float3 p = lv_project(lv, moved);
  r.uv = p.xy;
  r.depth = p.z;
  r.bias = 0.0f;
  r.biasSlope = 0.0f;
  r.texel = texel;
  r.valid = p.z > 0.0f && all(isfinite(p));
  return r;
}

// The slope-scaled bias of sc_receiver_unsloped's receiver at `position`. sc_depth_slope gives the same slope, bit for
// bit, for either sign of the normal (its tangent steps and their projections only change sign), so the normal need
// not be flipped as sc_receiver_unsloped flips it.
inline Receiver sc_receiver_sloped(__constant const LightViewGpu* lv, Receiver r, float3 position, float3 normal,
                                   ShadowBias bias) {
  float tanTheta = sc_depth_slope(lv, position, normal, r.texel);
  r.bias = r.texel * (bias.base + bias.slope * tanTheta);
  r.biasSlope = r.texel * tanTheta;
  return r;
}

inline Receiver sc_receiver(__constant const LightViewGpu* lv, float3 position, float3 normal, ShadowBias bias) {
  return sc_receiver_sloped(lv, sc_receiver_unsloped(lv, position, normal, bias), position, normal, bias);
}

// A G-buffer neighbour counts for the footprint only when it lies near the pixel's tangent plane:
// |n . (q - p)| <= SHADOW_PLANE_TOLERANCE |q - p| (about 15 degrees), so silhouettes do not blow up filters.
#define SHADOW_PLANE_TOLERANCE 0.25f

// (texel x, texel y, light depth) offset from the pixel (projected at `here`) to G-buffer neighbour j, or 0
// when j is background or off the pixel's plane.
inline float3 sc_neighbour_delta(__global const float4* position, __constant const LightViewGpu* lv, float3 p,
                                 float3 n, float3 here, uint j) {
  float4 q = position[j];
  float3 d = q.xyz - p;
  if (q.w == 0.0f || fabs(dot(n, d)) > SHADOW_PLANE_TOLERANCE * length(d)) return (float3)(0.0f);
  float3 delta = lv_project(lv, q.xyz) - here;
  return all(isfinite(delta)) ? delta : (float3)(0.0f);
}

// The pixel's screen-x and screen-y steps in the map (texels and light depth): finite differences towards
// the +1 neighbour, else the -1 neighbour; a zero step where neither lies on the pixel's plane. G-buffer rows
// are `width` pixels, pixel i = y * width + x.
typedef struct Footprint {
  float3 dx, dy;
} Footprint;

inline Footprint sc_footprint(__global const float4* position, __constant const LightViewGpu* lv, uint width,
                              uint height, uint i, float3 p, float3 n) {
  uint x = i % width, y = i / width;
  float3 here = lv_project(lv, p);
  Footprint f;
  f.dx = x + 1 < width ? sc_neighbour_delta(position, lv, p, n, here, i + 1) : (float3)(0.0f);
  if (all(f.dx == 0.0f) && x > 0) f.dx = -sc_neighbour_delta(position, lv, p, n, here, i - 1);
  f.dy = y + 1 < height ? sc_neighbour_delta(position, lv, p, n, here, i + width) : (float3)(0.0f);
  if (all(f.dy == 0.0f) && y > 0) f.dy = -sc_neighbour_delta(position, lv, p, n, here, i - width);
  return f;
}

// The footprint's size in texels: the longer screen step.
inline float sc_footprint_texels(Footprint f) { return max(length(f.dx.xy), length(f.dy.xy)); }

// Receiver-plane depth bias (Isidoro, "Shadow Mapping: GPU-based Tips and Techniques", GDC 2006): the
// gradient g = d(depth)/d(texel) of the receiver's plane from the screen-space Jacobian J = [dx.xy dy.xy] of
// its map coordinates and its depth steps (dx.z, dy.z): J^T g = (dx.z, dy.z). Comparing a texel centred at c
// against depth + g . (c - uv) compares the occluder with the receiver's own plane at that texel, instead of
// a bias that grows with the filter. Returns 0 in `valid` when J is singular (a missing neighbour, an
// edge-on receiver) or the plane is steeper than SHADOW_MAX_SLOPE depth units per texel footprint.
typedef struct ReceiverPlane {
  float2 gradient;  // light depth per texel
  int valid;
} ReceiverPlane;

inline ReceiverPlane sc_receiver_plane(Footprint f, float texelWorld) {
  ReceiverPlane rp;
  float det = f.dx.x * f.dy.y - f.dy.x * f.dx.y;
  float scale = max(length(f.dx.xy), length(f.dy.xy));
  rp.valid = fabs(det) > 1e-6f * scale * scale && scale > 0.0f;
  // g = J^-T (dx.z, dy.z), with J^-T = [dy.y -dx.y; -dy.x dx.x] / det.
  rp.gradient = rp.valid ? (float2)(f.dy.y * f.dx.z - f.dx.y * f.dy.z, -f.dy.x * f.dx.z + f.dx.x * f.dy.z) / det
                         : (float2)(0.0f);
  if (!(all(isfinite(rp.gradient)) && length(rp.gradient) <= SHADOW_MAX_SLOPE * texelWorld)) {
    rp.valid = 0;
    rp.gradient = (float2)(0.0f);
  }
  return rp;
}

// The receiver plane of G-buffer pixel i when receiver-plane depth bias is `enabled`, else an invalid one (the
// slope-scaled bias applies); the footprint is only measured when it is needed.
inline ReceiverPlane sc_receiver_plane_at(int enabled, __global const float4* position,
                                          __constant const LightViewGpu* lv, uint width, uint height, uint i,
                                          float3 p, float3 n, float texelWorld) {
  ReceiverPlane none = {(float2)(0.0f), 0};
  return enabled ? sc_receiver_plane(sc_footprint(position, lv, width, height, i, p, n), texelWorld) : none;
}

// The receiver of a hard test (sm, fvsm, jittered) and its plane: sc_receiver with the slope-scaled bias computed
// only where the plane is unknown, the one case sc_hard_lit reads it. Returns the receiver (valid 0: nothing to test).
inline Receiver sc_hard_receiver(int receiverPlane, __global const float4* position, __constant const LightViewGpu* lv,
                                 uint width, uint height, uint i, float3 p, float3 n, ShadowBias bias,
                                 ReceiverPlane* rp) {
  Receiver r = sc_receiver_unsloped(lv, p, n, bias);
  if (!r.valid) return r;
  *rp = sc_receiver_plane_at(receiverPlane, position, lv, width, height, i, p, n, r.texel);
  return rp->valid ? r : sc_receiver_sloped(lv, r, p, n, bias);
}

// Asks the caches (CPU devices, PN_PREFETCH) for the map texels within `reach` of where G-buffer pixel `ahead` projects
// (rows y - reach .. y + reach, the columns x - reach and x + reach of each), texels of `texelBytes` bytes; nothing for
// background or a point off the map. The shading kernels' map reads miss the caches: a 1920^2 map is 14 MiB, and
// neighbouring pixels land texels apart in it, the next frame row rows away (sm's one read took 86 % of its kernel's
// own time). Called for the pixel PN_PREFETCH_AHEAD work-items on; reach covers the pixel's normal offset too.
inline void sc_prefetch_texels(__global const float4* position, __constant const LightViewGpu* lv,
                               __global const void* map, uint texelBytes, int reach, uint ahead, uint count) {
#if PN_PREFETCHES
  int2 texel;
  if (!lv_pixel_texel(position, lv, ahead, count, &texel)) return;
  const int x = texel.x, y = texel.y;
  const int x0 = max(x - reach, 0), x1 = min(x + reach, lv->width - 1);
  __global const uchar* base = (__global const uchar*)map;
  for (int row = max(y - reach, 0); row <= min(y + reach, lv->height - 1); ++row) {
    const size_t first = (size_t)row * (size_t)lv->width;
    PN_PREFETCH(base + (first + (size_t)x0) * texelBytes);
    PN_PREFETCH(base + (first + (size_t)x1) * texelBytes);
  }
#endif
}

// Map depth at an integer texel; texels outside the map hold no occluder (+INFINITY).
inline float sc_fetch(__global const float* depth, int width, int height, int x, int y) {
  if (x < 0 || y < 0 || x >= width || y >= height) return INFINITY;
  return depth[y * width + x];
}

// 1 when the receiver at `depth` is lit by the occluder depth `occluder` (NaN and background lit).
inline float sc_lit(float occluder, float depth) { return occluder < depth ? 0.0f : 1.0f; }

// The hard test of sm: the nearest texel's occluder against the receiver's own plane at that texel's centre where
// the plane is known (planeBias: the constant bias, world units), else against the slope-biased depth.
inline float sc_hard_lit(__global const float* map, __constant const LightViewGpu* lv, Receiver r, ReceiverPlane rp,
                         float planeBias) {
  float2 texel = pn_floor2(r.uv);
  float occluder = sc_fetch(map, lv->width, lv->height, (int)texel.x, (int)texel.y);
  float depth = rp.valid ? r.depth - planeBias + dot(rp.gradient, texel + 0.5f - r.uv) : r.depth - r.bias;
  return sc_lit(occluder, depth);
}

// Bilinear-weighted comparison of the four texels around continuous texel coordinate `uv`.
inline float sc_compare_bilinear(__global const float* map, int width, int height, float2 uv, float depth) {
  float2 t = uv - 0.5f;
  float2 base = pn_floor2(t);
  float2 f = t - base;
  int x = (int)base.x, y = (int)base.y;
  float s00 = sc_lit(sc_fetch(map, width, height, x, y), depth);
  float s10 = sc_lit(sc_fetch(map, width, height, x + 1, y), depth);
  float s01 = sc_lit(sc_fetch(map, width, height, x, y + 1), depth);
  float s11 = sc_lit(sc_fetch(map, width, height, x + 1, y + 1), depth);
  return mix(mix(s00, s10, f.x), mix(s01, s11, f.x), f.y);
}

// Bilinear-weighted comparison at tap `uv` against the receiver's plane: texel k (centre c_k) is compared
// with depth + g . (c_k - origin), where `depth` is the (biased) receiver depth at map position `origin`.
inline float sc_compare_bilinear_plane(__global const float* map, int width, int height, float2 uv, float2 origin,
                                       float depth, float2 g) {
  float2 t = uv - 0.5f;
  float2 base = pn_floor2(t);
  float2 f = t - base;
  int x = (int)base.x, y = (int)base.y;
  float2 c = base + 0.5f - origin;  // centre of texel (x, y) relative to the receiver
  float s00 = sc_lit(sc_fetch(map, width, height, x, y), depth + dot(g, c));
  float s10 = sc_lit(sc_fetch(map, width, height, x + 1, y), depth + dot(g, c + (float2)(1.0f, 0.0f)));
  float s01 = sc_lit(sc_fetch(map, width, height, x, y + 1), depth + dot(g, c + (float2)(0.0f, 1.0f)));
  float s11 = sc_lit(sc_fetch(map, width, height, x + 1, y + 1), depth + dot(g, c + (float2)(1.0f, 1.0f)));
  return mix(mix(s00, s10, f.x), mix(s01, s11, f.x), f.y);
}

// sc_compare_bilinear_plane summed over the (2r+1)^2 taps at unit spacing around uv (offsets -r..r in x and y), each
// texel compared once: the taps' bilinear footprints tile the (2r+2)^2 texels from floor(uv - 0.5) - r, a texel's
// comparison (against the plane at its own centre) is the same in every tap that reads it, and it gathers those taps'
// bilinear weights, 1 - f at the first row and column, f at the last and 1 between (f the fraction of uv - 0.5): the
// taps' sum to rounding, with (2r+2)^2 fetches and comparisons instead of 4 (2r+1)^2 (pcf's unit grid: 64 for 196 at
// r = 3).
inline float sc_grid_plane_sum(__global const float* map, int width, int height, float2 uv, int radius, float depth,
                               float2 g) {
  const float2 t = uv - 0.5f, b = pn_floor2(t), f = t - b;
  const int x0 = (int)b.x - radius, y0 = (int)b.y - radius, n = 2 * radius + 2;
  float sum = 0.0f;
  for (int j = 0; j < n; ++j) {
    const float wy = j == 0 ? 1.0f - f.y : j == n - 1 ? f.y : 1.0f;
    float row = 0.0f;
    for (int k = 0; k < n; ++k) {
      const float wx = k == 0 ? 1.0f - f.x : k == n - 1 ? f.x : 1.0f;
      const float2 c = (float2)((float)(x0 + k), (float)(y0 + j)) + 0.5f - uv;  // texel centre from the receiver
      row += wx * sc_lit(sc_fetch(map, width, height, x0 + k, y0 + j), depth + dot(g, c));
    }
    sum += wy * row;
  }
  return sum;
}

// Sparse taps. A bilinear comparison smooths a tap's indicator over one texel, which is what a filter with a tap in
// every texel or two needs to move continuously. Where a kernel's taps each stand for SC_SPARSE_TAP_AREA texels or
// more (8 texels apart and wider), what its estimate misses is the shadow's shape between the taps, not that one
// texel's smoothing, and the four fetches cost four cache lines of a map much larger than the caches for one:
// sc_sparse_taps tells, and the filters then compare the texel under each tap (sc_compare_texel, sc_tap_texel).
// Measured (pcss, `--pcss-sparse-taps on,off`, 256-spp references; docs/techniques/sm-pcf-pcss.md, "Sparse taps"):
// scenes/default.json at 640x360, MAE 0.001315 -> 0.001320 and its shading 2-3 ms (8 %) faster; at 16 texels a tap
// 3 ms for 0.001321, but the staircase at 4096^2 then lost 2.3 % (at 64: 0.7 %).
#define SC_SPARSE_TAP_AREA 64.0f

// Whether `taps` taps over a kernel of `area` texels are sparse (above).
inline int sc_sparse_taps(float taps, float area) { return taps * SC_SPARSE_TAP_AREA <= area; }

// The comparison of the texel under continuous texel coordinate `uv` (1 lit, 0 blocked): against the receiver's plane
// at the texel's centre (`depth` the biased receiver depth at map position `origin`, g its gradient) where `plane`,
// else against `depth` itself.
inline float sc_compare_texel(__global const float* map, int width, int height, float2 uv, float2 origin, float depth,
                              float2 g, int plane) {
  const float2 texel = pn_floor2(uv);
  const float occluder = sc_fetch(map, width, height, (int)texel.x, (int)texel.y);
  return sc_lit(occluder, plane ? depth + dot(g, texel + 0.5f - origin) : depth);
}

// One filter tap at texel offset `offset` from the receiver: against the receiver's plane where it is known
// (planeBias: the constant bias, world units), else with the slope-scaled bias growing with the offset.
inline float sc_tap(__global const float* map, __constant const LightViewGpu* lv, Receiver r, ReceiverPlane rp,
                    float planeBias, float2 offset) {
  if (rp.valid)
    return sc_compare_bilinear_plane(map, lv->width, lv->height, r.uv + offset, r.uv, r.depth - planeBias,
                                     rp.gradient);
  return sc_compare_bilinear(map, lv->width, lv->height, r.uv + offset, r.depth - r.bias - r.biasSlope * length(offset));
}

// sc_tap where the kernel's taps are sparse (sc_sparse_taps): the texel under the tap alone. pcss chooses between the
// two once per pixel and loops over one of them: a choice per tap costs PoCL's vectorized work-groups about half of
// what the texel saves (pcss on scenes/default.json at one tap per 16 texels: 2.5 against 5.5 ms of shading). pcf,
// whose defaults never reach sparse taps, chooses per tap.
inline float sc_tap_texel(__global const float* map, __constant const LightViewGpu* lv, Receiver r, ReceiverPlane rp,
                          float planeBias, float2 offset) {
  if (rp.valid)
    return sc_compare_texel(map, lv->width, lv->height, r.uv + offset, r.uv, r.depth - planeBias, rp.gradient, 1);
  return sc_compare_texel(map, lv->width, lv->height, r.uv + offset, r.uv,
                          r.depth - r.bias - r.biasSlope * length(offset), (float2)(0.0f), 0);
}

#endif
