// LiSPSM for directional lights (Wimmer et al. 2004, sec. 4-5): the body B as the convex hull of the camera frustum
// slice clipped to the scene box, seen along the light; a perspective warp along the view direction projected
// perpendicular to the light with the projection centre n in front of B; the map window fitted to B in the warped
// space. Everything is in the light's eye space, so the stored depth stays the light's linear depth.
#include "host/pipeline/lispsm.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "host/pipeline/splits.h"

namespace penumbra {
namespace {

using Plane = glm::dvec4;  // f(p) = dot(xyz, p) + w >= 0 inside

// The segment a-b clipped to every plane (Liang-Barsky); appends its end points when something is left.
void clipSegment(const glm::dvec3& a, const glm::dvec3& b, const std::vector<Plane>& planes,
                 std::vector<glm::dvec3>& out) {
  double t0 = 0.0, t1 = 1.0;
  for (const Plane& p : planes) {
    const double fa = glm::dot(glm::dvec3(p), a) + p.w, fb = glm::dot(glm::dvec3(p), b) + p.w;
    if (fa < 0 && fb < 0) return;
    if (fa < 0) t0 = std::max(t0, fa / (fa - fb));
    if (fb < 0) t1 = std::min(t1, fa / (fa - fb));
    if (t0 > t1) return;
  }
  out.push_back(a + t0 * (b - a)), out.push_back(a + t1 * (b - a));
}

// The 12 edges of a box-like solid whose 8 corners are indexed by 3 bits (corners differing in one bit).
void clipEdges(const std::array<glm::dvec3, 8>& c, const std::vector<Plane>& planes, std::vector<glm::dvec3>& out) {
  for (int i = 0; i < 8; ++i)
    for (int bit : {1, 2, 4})
      if (!(i & bit)) clipSegment(c[i], c[i | bit], planes, out);
}

// Vertices of (camera frustum between near and far) ∩ (scene box): every vertex of the intersection of two convex
// solids lies on an edge of one of them inside the other, so these points span the same convex hull.
std::vector<glm::dvec3> bodyPoints(const Camera& camera, float near, float far, const Bounds& scene) {
  const std::vector<glm::vec3> fc = frustumSliceCorners(camera, near, far);  // bit 0: x, bit 1: y, bit 2: far
  std::array<glm::dvec3, 8> frustum, box;
  for (int i = 0; i < 8; ++i) {
    frustum[i] = glm::dvec3(fc[i]);
    box[i] = {i & 1 ? scene.max.x : scene.min.x, i & 2 ? scene.max.y : scene.min.y, i & 4 ? scene.max.z : scene.min.z};
  }
  const double slack = 1e-6 * std::max<double>(scene.radius(), 1e-6);  // keeps corners on a face inside
  std::vector<Plane> boxPlanes;
  for (int axis = 0; axis < 3; ++axis) {
    glm::dvec3 n(0.0);
    n[axis] = 1.0;
    boxPlanes.push_back(Plane(n, -double(scene.min[axis]) + slack));
    boxPlanes.push_back(Plane(-n, double(scene.max[axis]) + slack));
  }
  // Frustum planes in camera eye space (depth v = -z), carried to world space: f_world(p) = f_eye(V p).
  const glm::dmat4 view(camera.view());
  const double ty = std::tan(glm::radians(double(camera.fovYDeg)) * 0.5), tx = ty * camera.aspect();
  const Plane eyePlanes[6] = {{0, 0, -1, -near}, {0, 0, 1, far}, {-1, 0, -tx, 0}, {1, 0, -tx, 0},
                              {0, -1, -ty, 0},   {0, 1, -ty, 0}};
  std::vector<Plane> frustumPlanes;
  for (const Plane& e : eyePlanes) {
    Plane w = e * view;  // row vector times matrix
    w.w += slack * glm::length(glm::dvec3(w));
    frustumPlanes.push_back(w);
  }
  std::vector<glm::dvec3> points;
  clipEdges(frustum, boxPlanes, points);
  clipEdges(box, frustumPlanes, points);
  return points;
}

double cross(const glm::dvec2& o, const glm::dvec2& a, const glm::dvec2& b) {
  return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

// Counter-clockwise convex hull (Andrew's monotone chain).
std::vector<glm::dvec2> convexHull(std::vector<glm::dvec2> p) {
  std::sort(p.begin(), p.end(), [](const glm::dvec2& a, const glm::dvec2& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
  if (p.size() < 3) return p;
  std::vector<glm::dvec2> h(2 * p.size());
  size_t k = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && cross(h[k - 2], h[k - 1], p[i]) <= 0) --k;
    h[k++] = p[i];
  }
  for (size_t i = p.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && cross(h[k - 2], h[k - 1], p[i]) <= 0) --k;
    h[k++] = p[i];
  }
  h.resize(k - 1);
  return h;
}

// The convex polygon cut to coordinate `axis` >= bound (sign 1) or <= bound (sign -1): one Sutherland-Hodgman pass.
std::vector<glm::dvec2> cutPolygon(const std::vector<glm::dvec2>& poly, int axis, double bound, double sign) {
  std::vector<glm::dvec2> out;
  for (size_t i = 0; i < poly.size(); ++i) {
    const glm::dvec2 &p = poly[i], &q = poly[(i + 1) % poly.size()];
    const double dp = sign * (p[axis] - bound), dq = sign * (q[axis] - bound);
    if (dp >= 0) out.push_back(p);
    if ((dp >= 0) != (dq >= 0)) out.push_back(p + (dp / (dp - dq)) * (q - p));
  }
  return out;
}

// World width of the longer side of a texel at light-eye (x, y) under P (rows x, y, w independent of z_eye):
// J = d(texel u, v)/d(x, y); the columns of J^-1 are the world steps of one texel, lengths |J row| / |det J|.
double texelAt(const glm::dmat4& P, int size, double x, double y) {
  const glm::dvec4 clip = P * glm::dvec4(x, y, 0.0, 1.0);
  const double half = 0.5 * size, nx = clip.x / clip.w, ny = clip.y / clip.w;
  const glm::dvec2 gu = glm::dvec2(P[0][0] - nx * P[0][3], P[1][0] - nx * P[1][3]) * (half / clip.w);
  const glm::dvec2 gv = glm::dvec2(P[0][1] - ny * P[0][3], P[1][1] - ny * P[1][3]) * (half / clip.w);
  return std::max(glm::length(gu), glm::length(gv)) / std::abs(gu.x * gv.y - gu.y * gv.x);
}

void setRows(pn_float4 rows[4], const glm::dmat4& m) {
  for (int r = 0; r < 4; ++r)
    rows[r] = {{float(m[0][r]), float(m[1][r]), float(m[2][r]), float(m[3][r])}};
}

struct Range {
  double lo = INFINITY, hi = -INFINITY;
  void grow(double v) { lo = std::min(lo, v), hi = std::max(hi, v); }
  double center() const { return 0.5 * (lo + hi); }
  double half() const { return 0.5 * (hi - lo); }
};

// B seen along the light: the light-eye (x, y) hull of the frustum slice inside the scene, cut to the receivers.
std::vector<glm::dvec2> bodyFootprint(const LispsmInput& in, const Bounds& scene, const glm::dmat4& eye) {
  std::vector<glm::dvec2> xy;
  for (const glm::dvec3& p : bodyPoints(in.camera, in.nearDepth, in.farDepth, scene))
    xy.push_back(glm::dvec2(eye * glm::dvec4(p, 1.0)));
  std::vector<glm::dvec2> body = convexHull(xy);
  if (in.receivers != nullptr && !in.receivers->empty)
    for (int axis = 0; axis < 2; ++axis) {
      body = cutPolygon(body, axis, in.receivers->lo[axis], 1.0);
      body = cutPolygon(body, axis, in.receivers->hi[axis], -1.0);
    }
  return body;
}

// Light space in light-eye (x, y): w (Wimmer's z) the view direction projected perpendicular to the light, u across
// it. Exactly parallel views have no projection: any axis will do, the warp is uniform there.
struct Axes {
  glm::dvec2 u, w;
  double sinGamma, gammaDeg;
};

Axes lightSpaceAxes(const glm::dmat4& eye, const Camera& camera) {
  const glm::dvec3 view = glm::dmat3(eye) * glm::normalize(glm::dvec3(camera.target - camera.eye));
  Axes a;
  a.sinGamma = std::min(glm::length(glm::dvec2(view)), 1.0);
  a.gammaDeg = glm::degrees(std::atan2(glm::length(glm::dvec2(view)), -view.z));  // the light travels along -z
  a.w = a.sinGamma > 1e-9 ? glm::dvec2(view) / a.sinGamma : glm::dvec2(0.0, 1.0);
  a.u = glm::dvec2(a.w.y, -a.w.x);
  return a;
}

// The warp: n, the projection centre (sc, tc) in (u, w) coordinates, and B's range in the warped coordinates
// x' = (s - sc) / t', z' = 1 / t' with t' = t - tc >= n. Both are linear-fractional, so their extremes over the
// convex body are at its vertices.
struct Warp {
  double n, nOpt, depthB, sc, tc;
  Range xw, zw;
};

Warp chooseWarp(const LispsmInput& in, const std::vector<glm::dvec2>& body, const Axes& a, const glm::dmat4& eye,
                double minExtent) {
  Range s, t;
  for (const glm::dvec2& p : body) s.grow(glm::dot(a.u, p)), t.grow(glm::dot(a.w, p));
  Warp warp;
  warp.depthB = std::max(t.hi - t.lo, minExtent);
  // Wimmer's n_opt, generalised by 1 / sin(gamma); clamped where the warp is uniform anyway.
  const double zn = std::max<double>(in.nearDepth, 1e-6), zf = std::max<double>(in.farDepth, zn);
  warp.nOpt = a.sinGamma > 0 ? (zn + std::sqrt(zn * zf)) / a.sinGamma : INFINITY;
  warp.n = std::clamp(in.n > 0 ? double(in.n) : warp.nOpt, 1e-6 * warp.depthB, kLispsmMaxNOverDepth * warp.depthB);
  const glm::dvec2 eyeXY(eye * glm::dvec4(glm::dvec3(in.camera.eye), 1.0));
  warp.tc = t.lo - warp.n, warp.sc = std::clamp(glm::dot(a.u, eyeXY), s.lo, s.hi);
  for (const glm::dvec2& p : body) {
    const double tp = glm::dot(a.w, p) - warp.tc;
    warp.xw.grow((glm::dot(a.u, p) - warp.sc) / tp), warp.zw.grow(1.0 / tp);
  }
  warp.zw.grow(1.0 / (warp.n + warp.depthB));  // a body thinner than minExtent still spans some texels
  return warp;
}

// Light-eye -> clip, rows over (x, y, z, 1) with t' = w.x x + w.y y - tc and light depth d = -z: x_c = x' t',
// y_c = z' t' (each mapped to [-1, 1] over B shrunk by `keep` for the margin), w_c = t', and
// z_c / w_c = 1 - 2 (r - r_lo) / (r_hi - r_lo) over r = d / t' (post-perspective light depth). Near clipping then
// keeps r <= r_hi: everything between the light and the body (same t', smaller depth) stays.
glm::dmat4 warpMatrix(const Warp& warp, const Axes& a, double zNear, double zFar, double keep, double minExtent) {
  const double hx = std::max(warp.xw.half(), 0.5 * minExtent / (warp.n + warp.depthB)) / keep;
  const double hz = warp.zw.half() / keep;
  const double rLo = 0.99 * zNear / (warp.n + warp.depthB), rHi = 1.01 * zFar / warp.n;
  const double az = 2.0 / (rHi - rLo), bz = 1.0 + az * rLo;
  const double xs = 1.0 / hx, xt = -warp.xw.center() / hx, yt = -warp.zw.center() / hz, y1 = 1.0 / hz;
  glm::dmat4 P(0.0);
  for (int c = 0; c < 2; ++c) {
    P[c][0] = xs * a.u[c] + xt * a.w[c];
    P[c][1] = yt * a.w[c];
    P[c][2] = bz * a.w[c];
    P[c][3] = a.w[c];
  }
  P[2][2] = az;  // z_c = bz t' - az d = bz t' + az z
  P[3][0] = -xs * warp.sc - xt * warp.tc, P[3][1] = -yt * warp.tc + y1, P[3][2] = -bz * warp.tc, P[3][3] = -warp.tc;
  return P;
}

}  // namespace

std::string LispsmFit::describe() const {
  if (!warped) return "lispsm: empty body, uniform map";
  return fmt::format("lispsm n {:.6g} (n_opt {:.6g}, gamma {:.3g} deg), texel {:.4g}..{:.4g}", n, nOpt, gammaDeg,
                     texelMin, texelMax);
}

LightView fitLispsmView(const LispsmInput& in, LispsmFit* fit) {
  if (in.light.type == LightType::Spot)
    throw std::invalid_argument("--warp lispsm: only directional lights are supported (spot lights are not)");
  // The uniform view supplies the light's eye space, its depth range (every caster towards the light: B extruded)
  // and the light's own terms; only the projection and the texel terms change.
  LightView lv = fitLightView(in.light, in.scene, in.size, in.receivers, in.marginTexels);
  LispsmFit result;
  const Bounds scene = in.scene.orUnit();
  const glm::dmat4 eye(lv.raster.view);
  const std::vector<glm::dvec2> body = bodyFootprint(in, scene, eye);
  if (body.empty()) {
    if (fit != nullptr) *fit = result;
    return lv;
  }
  const Axes axes = lightSpaceAxes(eye, in.camera);
  const double minExtent = 1e-4 * std::max<double>(scene.radius(), 1e-6);
  const Warp warp = chooseWarp(in, body, axes, eye, minExtent);
  const double keep = 1.0 - std::min(2.0 * std::max(in.marginTexels, 0.0f) / in.size, 0.5);
  const glm::dmat4 P = warpMatrix(warp, axes, lv.gpu.zNear, lv.gpu.zFar, keep, minExtent);
  result.warped = true;
  result.n = float(warp.n), result.nOpt = float(warp.nOpt), result.gammaDeg = float(axes.gammaDeg);
  double texelMin = INFINITY, texelMax = 0;
  for (const glm::dvec2& p : body) {
    const double texel = texelAt(P, in.size, p.x, p.y);
    texelMin = std::min(texelMin, texel), texelMax = std::max(texelMax, texel);
  }
  result.texelMin = float(texelMin), result.texelMax = float(texelMax);
  lv.raster.projection = glm::mat4(P);
  setRows(lv.gpu.projection, P);
  lv.gpu.warp = LIGHT_WARP_PERSPECTIVE;
  lv.gpu.texelScale = float(std::sqrt(texelMin * texelMax));  // a typical texel, for filter scales between maps
  if (fit != nullptr) *fit = result;
  return lv;
}

}  // namespace penumbra
