// Triangle setup, stage 1 of 4 (Laine & Karras 2011, section 4.1): world -> clip transform, clipping against the
// near plane and the guard band, snapping to 1/256 pixel, culling, and the record each triangle's exact edge functions
// come from (raster/types.h).
// One work-item per input triangle. The first triangle it yields goes to the input triangle's own record (written
// even when dropped, as invalid); further fan triangles from clipping are appended past triangleCount through
// counters->extraTriangles, written only below extraCapacity (the host grows the buffer and re-runs).
//
// The snapping spec, bit-exact on every device with fp64 (tests/reference/raster_ref.cpp implements it on its own):
//   clip = ((M[0] x + M[1] y) + M[2] z) + M[3] in double, from the float matrix and float position: every product
//          is exact, so no compiler's fused multiply-add can change the result;
//   clipping: Sutherland-Hodgman against z_c + w_c >= 0, then x_c + G w_c >= 0, G w_c - x_c >= 0, the same for y;
//          an edge is cut from its inside vertex, v = v_in + t (v_out - v_in) with t = d_in / (d_in - d_out), so a
//          shared edge is cut identically in both triangles (no cracks); fan from polygon vertex 0;
//   X = rint((x_c / w_c + 1) * width * 128), Y likewise, in subpixels (double division is correctly rounded);
//   view depth -z_eye per vertex: separable projections ((c0 z_c + c1 w_c) + c2), general ones
//          (((g0 x_c + g1 y_c) + g2 z_c) + g3 w_c), float coefficients times double clip coordinates.
// Supported range: viewports up to 8192^2, coordinates up to 2^19 .. 2^20 pixels beyond the viewport (guard band,
// raster/constants.h). Without fp64 the same steps run in float: still watertight, but not bit-equal to the
// reference, and clipping far outside the view loses depth accuracy (1e-3 relative at 2e5 units).
#include "raster/constants.h"
#include "raster/types.h"

#ifdef PENUMBRA_HAS_FP64
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
typedef double real;
typedef double4 real4;
#else
typedef float real;
typedef float4 real4;
#endif
// The clip interpolation v_in + t (v_out - v_in) is the one place where a fused multiply-add would round
// differently; keep the device and the reference on the same arithmetic.
#pragma OPENCL FP_CONTRACT OFF

static real setupRow(const RasterViewParams* p, int row, float3 v) {
  return (((real)p->clip[row] * (real)v.x + (real)p->clip[4 + row] * (real)v.y) + (real)p->clip[8 + row] * (real)v.z) +
         (real)p->clip[12 + row];
}

static real4 setupTransform(const RasterViewParams* p, float3 v) {
  return (real4)(setupRow(p, 0, v), setupRow(p, 1, v), setupRow(p, 2, v), setupRow(p, 3, v));
}

// Signed distance to clip plane `plane` (>= 0 inside): near, then the guard band left, right, bottom, top.
static real setupPlaneDistance(real4 v, int plane, real gx, real gy) {
  switch (plane) {
    case 0:
      return v.z + v.w;
    case 1:
      return v.x + gx * v.w;
    case 2:
      return gx * v.w - v.x;
    case 3:
      return v.y + gy * v.w;
    default:
      return gy * v.w - v.y;
  }
}

// One Sutherland-Hodgman pass; returns the output vertex count (at most n + 1).
static int setupClipPlane(const real4* in, int n, real4* out, int plane, real gx, real gy) {
  int m = 0;
  for (int i = 0; i < n; ++i) {
    real4 p = in[i], q = in[i + 1 < n ? i + 1 : 0];
    real dp = setupPlaneDistance(p, plane, gx, gy), dq = setupPlaneDistance(q, plane, gx, gy);
    if (dp >= 0) out[m++] = p;
    if ((dp >= 0) != (dq >= 0)) {
      real4 vin = dp >= 0 ? p : q, vout = dp >= 0 ? q : p;
      real din = dp >= 0 ? dp : dq, dout = dp >= 0 ? dq : dp;
      real t = din / (din - dout);
      out[m++] = vin + t * (vout - vin);
    }
  }
  return m;
}

// The snapping and per-vertex terms as expressions valid for scalars and vectors alike, so that the scalar path and
// the CPU path below compute every value with the same operations. Window coordinate (before rounding) from the clip
// coordinate x, w and the half size s in subpixels; view depth -z_eye from z_c, w_c.
#define SETUP_WINDOW(x, w, s) (((x) / (w) + (real)1) * (s))
#define SETUP_VIEW_Z(p, z, w) ((p)->viewZFromClip[0] * (z) + (p)->viewZFromClip[1] * (w) + (p)->viewZFromClip[2])
// The general form (p->generalProjection): -z_eye from all four clip coordinates, summed in this order.
#define SETUP_VIEW_Z_GENERAL(p, x, y, z, w)                                                   \
  ((((p)->viewZGeneral[0] * (x) + (p)->viewZGeneral[1] * (y)) + (p)->viewZGeneral[2] * (z)) + \
   (p)->viewZGeneral[3] * (w))
// View depth of clip vertex v: the separable formula unchanged (bit for bit as before), else the general one.
#define SETUP_VIEW_Z_OF(p, v) \
  ((p)->generalProjection ? SETUP_VIEW_Z_GENERAL(p, (v).x, (v).y, (v).z, (v).w) : SETUP_VIEW_Z(p, (v).z, (v).w))

// Snapped window position in subpixels.
static int2 setupSnap(real4 v, real sx, real sy) {
  real x = rint(SETUP_WINDOW(v.x, v.w, sx)), y = rint(SETUP_WINDOW(v.y, v.w, sy));
  x = clamp(x, (real)-RASTER_COORD_LIMIT, (real)RASTER_COORD_LIMIT);
  y = clamp(y, (real)-RASTER_COORD_LIMIT, (real)RASTER_COORD_LIMIT);
  return (int2)((int)x, (int)y);
}

#ifndef RASTER_SETUP_VECTOR
#define RASTER_SETUP_VECTOR 0
#endif
#if RASTER_SETUP_VECTOR && defined(PENUMBRA_HAS_FP64)
// CPU path (RASTER_SETUP_VECTOR, from the work-group table): a triangle's twelve divisions in two 8-wide ones (IEEE
// division is correctly rounded in every lane, so the results are those of the scalar path) and rint without
// branches: PoCL's double rint is a branchy library call. (x + 1.5 * 2^52) - 1.5 * 2^52 rounds to nearest even
// exactly for |x| <= 2^51; beyond, it is monotonic and keeps the sign, so after the clamp to +-2^29 it equals
// clamp(rint(x)) for every x, infinities included (w > 0 rules out NaN). FP_CONTRACT is off and no fast-math
// option is given, so the compiler may not fold the two additions.
#define SETUP_RINT(x) (((x) + 0x1.8p52) - 0x1.8p52)
// Orthographic views have w = 1 at every vertex (clipping keeps it: 1 + t (1 - 1)); x / 1 == x exactly in IEEE
// arithmetic, so skipping those divisions changes no bit of any result.
static bool setupUnitW(const real4* v) { return v[0].w == 1 && v[1].w == 1 && v[2].w == 1; }

static void setupSnapVector(const real4* v, real sx, real sy, int2* s) {
  const double8 x = (double8)(v[0].x, v[1].x, v[2].x, v[0].y, v[1].y, v[2].y, 0, 0);
  const double8 size = (double8)(sx, sx, sx, sy, sy, sy, 0, 0);
  const double8 w = (double8)(v[0].w, v[1].w, v[2].w, v[0].w, v[1].w, v[2].w, 1, 1);
  const double8 q = setupUnitW(v) ? (x + 1) * size : SETUP_WINDOW(x, w, size);
  const int8 i = convert_int8(clamp(SETUP_RINT(q), (double)-RASTER_COORD_LIMIT, (double)RASTER_COORD_LIMIT));
  s[0] = (int2)(i.s0, i.s3), s[1] = (int2)(i.s1, i.s4), s[2] = (int2)(i.s2, i.s5);
}

// invW and viewZOverW of the (oriented) vertices v[0..2].
static void setupVertexTermsVector(const real4* v, const RasterViewParams* p, float* invW, float* viewZOverW) {
  const double4 w = (double4)(v[0].w, v[1].w, v[2].w, 1);
  const double4 z = (double4)(v[0].z, v[1].z, v[2].z, 0);
  const double4 viewZ = p->generalProjection ? SETUP_VIEW_Z_GENERAL(p, (double4)(v[0].x, v[1].x, v[2].x, 0),
                                                                    (double4)(v[0].y, v[1].y, v[2].y, 0), z, w)
                                             : SETUP_VIEW_Z(p, z, w);
  const double8 n = (double8)((double4)1, viewZ);
  const float8 t = convert_float8(setupUnitW(v) ? n : n / (double8)(w, w));
  invW[0] = t.s0, invW[1] = t.s1, invW[2] = t.s2;
  viewZOverW[0] = t.s4, viewZOverW[1] = t.s5, viewZOverW[2] = t.s6;
}
#else
#undef RASTER_SETUP_VECTOR
#define RASTER_SETUP_VECTOR 0
#endif

// The record of a dropped triangle: every field written (0; the valid flag clear), so that no reader, and no checker
// of uninitialised values such as Oclgrind's, ever sees indeterminate bytes stored for it.
static RasterTriangle setupRejected(uint id) {
  RasterTriangle r;
  for (int k = 0; k < 3; ++k) r.x[k] = 0, r.y[k] = 0, r.invW[k] = 0.0f, r.viewZOverW[k] = 0.0f;
  for (int k = 0; k < 4; ++k) r.bbox[k] = 0;
  r.triangleId = id;
  r.flags = 0;
  return r;
}

// Builds the record of one clip-space triangle; returns false (record invalid) when it is dropped: w <= 0,
// zero snapped area (not in conservative draws), wound the way `cull` drops (RASTER_CULL_*), or no pixel centre of the
// scissor inside its bounds. `alpha`: the RASTER_FLAG_ALPHA bits of an alpha-tested triangle and
// RASTER_FLAG_NONCASTER (0 for others), added to the flags of a drawn record.
static bool setupEmit(real4 v0, real4 v1, real4 v2, const RasterViewParams* p, uint id, uint cull, uint alpha,
                      RasterTriangle* r) {
  *r = setupRejected(id);
  if (!(v0.w > 0 && v1.w > 0 && v2.w > 0)) return false;
  const real sx = (real)p->width * (RASTER_SUBPIXELS / 2), sy = (real)p->height * (RASTER_SUBPIXELS / 2);
  real4 v[3] = {v0, v1, v2};
#if RASTER_SETUP_VECTOR
  int2 s[3];
  setupSnapVector(v, sx, sy, s);
#else
  int2 s[3] = {setupSnap(v0, sx, sy), setupSnap(v1, sx, sy), setupSnap(v2, sx, sy)};
#endif
  long area = (long)(s[1].x - s[0].x) * (s[2].y - s[0].y) - (long)(s[2].x - s[0].x) * (s[1].y - s[0].y);
  // Conservative draws keep zero-area records (slivers thinner than a subpixel after snapping): their edge tests still
  // pass wherever the dilated rectangle meets the snapped segment, and the exact test downstream decides.
  if ((area == 0 && !p->conservative) || (cull == RASTER_CULL_CW && area < 0) || (cull == RASTER_CULL_CCW && area > 0))
    return false;
  if (area < 0) {  // make it counter-clockwise: edge functions positive inside
    int2 ts = s[1];
    s[1] = s[2];
    s[2] = ts;
    real4 tv = v[1];
    v[1] = v[2];
    v[2] = tv;
  }
  // Pixels whose centre can be inside: ceil((min - 128) / 256) .. floor((max - 128) / 256), cut to the scissor.
  // Conservative draws: pixels whose area, dilated by RASTER_CONSERVATIVE_DILATION, can meet the triangle's box:
  // floor((min - D) / 256) .. floor((max + D) / 256), as -floor(-x) = ceil(x) keeps every shift non-negative.
  int minX = min(s[0].x, min(s[1].x, s[2].x)), maxX = max(s[0].x, max(s[1].x, s[2].x));
  int minY = min(s[0].y, min(s[1].y, s[2].y)), maxY = max(s[0].y, max(s[1].y, s[2].y));
  const int lo = p->conservative ? RASTER_SUBPIXELS - 1 + RASTER_CONSERVATIVE_DILATION : RASTER_SAMPLE_OFFSET;
  const int hi = p->conservative ? -RASTER_CONSERVATIVE_DILATION : RASTER_SAMPLE_OFFSET;
  int x0 = max(-((lo - minX) >> RASTER_SUBPIXEL_LOG2), p->rectX0);
  int y0 = max(-((lo - minY) >> RASTER_SUBPIXEL_LOG2), p->rectY0);
  int x1 = min((maxX - hi) >> RASTER_SUBPIXEL_LOG2, p->rectX1 - 1);
  int y1 = min((maxY - hi) >> RASTER_SUBPIXEL_LOG2, p->rectY1 - 1);
  if (x0 > x1 || y0 > y1) return false;
  r->bbox[0] = (ushort)x0, r->bbox[1] = (ushort)y0, r->bbox[2] = (ushort)x1, r->bbox[3] = (ushort)y1;
  uint flags = RASTER_FLAG_VALID;
#if RASTER_SETUP_VECTOR
  float invW[3], viewZOverW[3];
  setupVertexTermsVector(v, p, invW, viewZOverW);
#endif
  for (int k = 0; k < 3; ++k) {
    int j = k == 2 ? 0 : k + 1, o = k == 0 ? 2 : k - 1;  // edge k: vertex k -> j, opposite vertex o
    int dx = s[j].x - s[k].x, dy = s[j].y - s[k].y;
    r->x[k] = s[k].x;
    r->y[k] = s[k].y;
    // Top-left rule (y up, counter-clockwise): left edges run downwards, top edges run leftwards.
    if (dy < 0 || (dy == 0 && dx < 0)) flags |= RASTER_FLAG_OWNS_EDGE0 << k;
#if RASTER_SETUP_VECTOR
    r->invW[k] = invW[o];
    r->viewZOverW[k] = viewZOverW[o];
#else
    real viewZ = SETUP_VIEW_Z_OF(p, v[o]);
    r->invW[k] = (float)((real)1 / v[o].w);
    r->viewZOverW[k] = (float)(viewZ / v[o].w);
#endif
  }
  r->flags = flags | alpha;
  return true;
}

// Near-plane and guard-band clipping into a fan: the first triangle goes to `out[t]`, the others are appended.
// Returns how many are drawn.
static uint setupClipped(real4 c0, real4 c1, real4 c2, const RasterViewParams* p, uint t, uint cull, uint alpha,
                         __global RasterTriangle* out, __global RasterCounters* counters) {
  real4 poly[RASTER_MAX_CLIP_VERTICES], next[RASTER_MAX_CLIP_VERTICES];
  poly[0] = c0, poly[1] = c1, poly[2] = c2;
  int n = 3;
  for (int plane = 0; plane < RASTER_CLIP_PLANES && n >= 3; ++plane) {
    n = setupClipPlane(poly, n, next, plane, (real)p->guardX, (real)p->guardY);
    for (int i = 0; i < n; ++i) poly[i] = next[i];
  }
  RasterTriangle r;
  uint drawn = 0;
  if (n < 3) {
    out[t] = setupRejected(t);
    return 0;
  }
  drawn += setupEmit(poly[0], poly[1], poly[2], p, t, cull, alpha, &r);
  out[t] = r;
  for (int k = 2; k + 1 < n; ++k) {
    if (!setupEmit(poly[0], poly[k], poly[k + 1], p, t, cull, alpha, &r)) continue;
    uint slot = atomic_inc(&counters->extraTriangles);
    if (slot < p->extraCapacity) out[p->triangleCount + slot] = r;
    ++drawn;
  }
  return drawn;
}

static bool setupOutside(real4 v, int plane) {  // trivial reject against the view volume's sides and far plane
  switch (plane) {
    case 0:
      return v.z + v.w < 0;
    case 1:
      return v.z > v.w;
    case 2:
      return v.x < -v.w;
    case 3:
      return v.x > v.w;
    case 4:
      return v.y < -v.w;
    default:
      return v.y > v.w;
  }
}

// The culling decision (RASTER_CULL_*) from the view, the triangle's material bits (RASTER_TRI_*) and, where the
// view drops the far sides of solids, its solid code; and the record's alpha flags from the material bits.
static uint setupCulls(const RasterViewParams* p, uint bits, __global const uchar* solidSides, uint t) {
  if (p->cullBackFaces || (p->cullSingleSided && (bits & RASTER_TRI_SINGLE_SIDED) != 0)) return RASTER_CULL_CW;
  return p->solidSides ? solidSides[t] : RASTER_CULL_NONE;
}
static uint setupAlphaFlags(uint bits) {
  return (bits & RASTER_TRI_ALPHA) != 0
             ? RASTER_FLAG_ALPHA | (bits >> RASTER_TRI_ALPHA_SHIFT) << RASTER_FLAG_ALPHA_SHIFT
             : 0u;
}

// Whether the triangle (q0, q1, q2) can shadow no point of the view's receiver box from any point of its light
// (RasterView::casterLight): its plane has the whole light strictly on one side and every point of the box on the
// same side, or behind the plane by at most casterTolerance. A segment from such a point to a point of the light then
// stays on that side and crosses the triangle nowhere (beyond the tolerance, which depth comparisons' bias ignores
// anyway): a ground plane under everything, a room's walls around its light. Degenerate triangles are kept (setup
// drops them later).
static bool setupCastsNothing(const RasterViewParams* p, float3 q0, float3 q1, float3 q2) {
  const float3 n = cross(q1 - q0, q2 - q0);
  const float size = length(n);
  if (!(size > 0.0f) || !isfinite(size)) return false;
  const float3 light = (float3)(p->casterLight[0], p->casterLight[1], p->casterLight[2]);
  const float side = p->casterSource == RASTER_CASTERS_BALL ? dot(n, light - q0) : dot(n, light);
  if (!(fabs(side) > p->casterLight[3] * size)) return false;  // the plane cuts the light (or touches it)
  const float3 centre = (float3)(p->casterBoxCentre[0], p->casterBoxCentre[1], p->casterBoxCentre[2]);
  const float3 extent = (float3)(p->casterBoxHalf[0], p->casterBoxHalf[1], p->casterBoxHalf[2]);
  const float nearest = copysign(1.0f, side) * dot(n, centre - q0) - dot(fabs(n), extent);  // the box's corner
  return nearest >= -p->casterTolerance * size;
}

static uint setupTriangle(__global const float* positions, __global const uint* triangles,
                          __global const uint* triangleBits, __global const uchar* solidSides, uint t,
                          const RasterViewParams* p, __global RasterTriangle* out, __global RasterCounters* counters) {
  RasterTriangle r = setupRejected(t);
  uint3 idx = vload3(t, triangles);
  if (idx.x >= p->vertexCount || idx.y >= p->vertexCount || idx.z >= p->vertexCount) {
    out[t] = r;
    return 0;
  }
  float3 q0 = vload3(idx.x, positions), q1 = vload3(idx.y, positions), q2 = vload3(idx.z, positions);
  if (!all(isfinite(q0) && isfinite(q1) && isfinite(q2))) {  // NaN or infinite vertices are dropped
    out[t] = r;
    return 0;
  }
  const bool castsNothing = p->casterSource != RASTER_CASTERS_ALL && setupCastsNothing(p, q0, q1, q2);
  if (castsNothing && !p->casterTiles) {
    out[t] = r;
    return 0;
  }
  real4 c0 = setupTransform(p, q0), c1 = setupTransform(p, q1), c2 = setupTransform(p, q2);
  if (!all(isfinite(c0) && isfinite(c1) && isfinite(c2))) {  // overflow (float-only devices)
    out[t] = r;
    return 0;
  }
  for (int plane = 0; plane < 6; ++plane)
    if ((plane != 1 || !p->generalProjection) && setupOutside(c0, plane) && setupOutside(c1, plane) &&
        setupOutside(c2, plane)) {
      out[t] = r;
      return 0;
    }
  const real gx = p->guardX, gy = p->guardY;
  bool clip = false;
  for (int plane = 0; plane < RASTER_CLIP_PLANES; ++plane)
    clip = clip || setupPlaneDistance(c0, plane, gx, gy) < 0 || setupPlaneDistance(c1, plane, gx, gy) < 0 ||
           setupPlaneDistance(c2, plane, gx, gy) < 0;
  const uint bits = p->triangleBits ? triangleBits[t] : 0u;
  const uint cull = setupCulls(p, bits, solidSides, t);
  const uint alpha = setupAlphaFlags(bits) | (castsNothing ? RASTER_FLAG_NONCASTER : 0u);  // the record's own flags
  if (clip) return setupClipped(c0, c1, c2, p, t, cull, alpha, out, counters);
  bool drawn = setupEmit(c0, c1, c2, p, t, cull, alpha, &r);
  out[t] = r;
  return drawn ? 1 : 0;
}

// out: triangleCount + extraCapacity records. counters->extraTriangles must be 0 and counters->setUp 0 on entry.
// triangleBits: one entry per triangle when p.triangleBits is set, solidSides (RASTER_CULL_*) when p.solidSides is
// (else never read).
__kernel __attribute__((reqd_work_group_size(RASTER_WG_SETUP, 1, 1))) void setup_triangles(
    __global const float* positions, __global const uint* triangles, __global const uint* triangleBits,
    __global const uchar* solidSides, __global RasterTriangle* out, __global RasterCounters* counters,
    const RasterViewParams p) {
  const uint t = get_global_id(0), lid = get_local_id(0);
  const uint n =
      t < p.triangleCount ? setupTriangle(positions, triangles, triangleBits, solidSides, t, &p, out, counters) : 0;
#if RASTER_SETUP_VECTOR
  // CPUs run a work-group's items one after another: a plain sum by item 0 beats a locked add per item.
  __local uint drawnBy[RASTER_WG_SETUP];
  drawnBy[lid] = n;
  barrier(CLK_LOCAL_MEM_FENCE);
  if (lid == 0) {
    uint drawn = 0;
    for (int i = 0; i < RASTER_WG_SETUP; ++i) drawn += drawnBy[i];
    if (drawn != 0) atomic_add(&counters->setUp, drawn);
  }
#else
  __local uint drawn;
  if (lid == 0) drawn = 0;
  barrier(CLK_LOCAL_MEM_FENCE);
  if (n != 0) atomic_add(&drawn, n);
  barrier(CLK_LOCAL_MEM_FENCE);
  if (lid == 0 && drawn != 0) atomic_add(&counters->setUp, drawn);
#endif
}
