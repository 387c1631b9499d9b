// LiSPSM (Wimmer et al. 2004, sec. 4-5): the body B as the convex hull of the camera frustum slice clipped to the
// scene box, seen along the light; a perspective warp along the view direction projected perpendicular to the light
// with the projection centre n in front of B; the map window fitted to B in the warped space. Spot lights do this in
// the light's post-perspective space (the light directional there) and compose the warp with the light's perspective.
#include "host/views/lispsm.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "host/views/lispsm_geometry.h"

namespace penumbra {
namespace {

using namespace lispsm;  // NOLINT: the body geometry

// World width of the longer side of a texel at light-eye point e under P: J = d(texel u, v)/d(x, y) at fixed z_eye
// (across the light's axis, as a uniform spot map's texelScale * depth); the columns of J^-1 are the world steps of
// one texel, lengths |J row| / |det J|. kernels/shared/light_view.h's lv_texel_world_at is the same in float.
double texelAt(const glm::dmat4& P, int size, const glm::dvec3& e) {
  const glm::dvec4 clip = P * glm::dvec4(e, 1.0);
  const double half = 0.5 * size, nx = clip.x / clip.w, ny = clip.y / clip.w;
  const glm::dvec2 gu = glm::dvec2(P[0][0] - nx * P[0][3], P[1][0] - nx * P[1][3]) * (half / clip.w);
  const glm::dvec2 gv = glm::dvec2(P[0][1] - ny * P[0][3], P[1][1] - ny * P[1][3]) * (half / clip.w);
  return std::max(glm::length(gu), glm::length(gv)) / std::abs(gu.x * gv.y - gu.y * gv.x);
}

struct Extent {
  double lo = INFINITY, hi = -INFINITY;
  void grow(double v) { lo = std::min(lo, v), hi = std::max(hi, v); }
  double center() const { return 0.5 * (lo + hi); }
  double half() const { return 0.5 * (hi - lo); }
};

// B seen along a directional light: the light-eye (x, y) hull of the frustum slice inside the scene, cut to the
// receivers.
std::vector<glm::dvec2> bodyFootprint(const LispsmInput& in, const Bounds& scene, const glm::dmat4& eye) {
  const double slack = 1e-6 * std::max<double>(scene.radius(), 1e-6);  // keeps corners on a face inside
  std::vector<glm::dvec2> xy;
  for (const glm::dvec3& p : frustumBoxPoints(in.camera, in.nearDepth, in.farDepth, scene, slack))
    xy.push_back(glm::dvec2(eye * glm::dvec4(p, 1.0)));
  std::vector<glm::dvec2> body = convexHull(xy);
  if (in.receivers != nullptr && !in.receivers->empty)
    for (int axis = 0; axis < 2; ++axis) {
      body = cutPolygon(body, axis, in.receivers->lo[axis], 1.0);
      body = cutPolygon(body, axis, in.receivers->hi[axis], -1.0);
    }
  return body;
}

// Light space in the plane across the light (light-eye x, y; for a spot, post-perspective x, y): w (Wimmer's z) the
// view direction projected perpendicular to the light, u across it. Exactly parallel views have no projection: any
// axis will do, the warp is uniform there.
struct Axes {
  glm::dvec2 u, w;
  double sinGamma, gammaDeg;
};

Axes axesAlong(const glm::dvec2& projected, double sinGamma, double gammaDeg) {
  Axes a;
  a.sinGamma = std::min(sinGamma, 1.0);
  a.gammaDeg = gammaDeg;
  const double length = glm::length(projected);
  a.w = a.sinGamma > 1e-9 && length > 0 ? projected / length : glm::dvec2(0.0, 1.0);
  a.u = glm::dvec2(a.w.y, -a.w.x);
  return a;
}

Axes lightSpaceAxes(const glm::dmat4& eye, const Camera& camera) {
  const glm::dvec3 view = glm::dmat3(eye) * glm::normalize(glm::dvec3(camera.target - camera.eye));
  const double across = glm::length(glm::dvec2(view));
  return axesAlong(glm::dvec2(view), across, glm::degrees(std::atan2(across, -view.z)));  // light along -z
}

// The warp: n, the projection centre (sc, tc) in (u, w) coordinates, and B's range in the warped coordinates
// x' = (s - sc) / t', z' = 1 / t' with t' = t - tc >= n. Both are linear-fractional, so their extremes over the
// convex body are at its vertices.
struct Warp {
  double n, depthB, sc, tc;
  Extent s, t, xw, zw;
};

// B's ranges along the axes; depthB at least minExtent.
Warp bodyRanges(const std::vector<glm::dvec2>& body, const Axes& a, double minExtent) {
  Warp warp{};
  for (const glm::dvec2& p : body) warp.s.grow(glm::dot(a.u, p)), warp.t.grow(glm::dot(a.w, p));
  warp.depthB = std::max(warp.t.hi - warp.t.lo, minExtent);
  return warp;
}

// n clamped where the warp is uniform anyway (kLispsmMaxNOverDepth), the centre n in front of B, laterally at the
// camera's `anchor` (u coordinate) kept within B, and B's warped ranges.
void placeWarp(Warp& warp, const std::vector<glm::dvec2>& body, const Axes& a, double n, double anchor) {
  warp.n = std::clamp(n, 1e-6 * warp.depthB, kLispsmMaxNOverDepth * warp.depthB);
  warp.tc = warp.t.lo - warp.n, warp.sc = std::clamp(anchor, warp.s.lo, warp.s.hi);
  for (const glm::dvec2& p : body) {
    const double tp = glm::dot(a.w, p) - warp.tc;
    warp.xw.grow((glm::dot(a.u, p) - warp.sc) / tp), warp.zw.grow(1.0 / tp);
  }
  warp.zw.grow(1.0 / (warp.n + warp.depthB));  // a body thinner than minExtent still spans some texels
}

// Wimmer's n_opt, generalised by 1 / sin(gamma); infinite for a view along the light.
double optimalN(const LispsmInput& in, double sinGamma) {
  const double zn = std::max<double>(in.nearDepth, 1e-6), zf = std::max<double>(in.farDepth, zn);
  return sinGamma > 0 ? (zn + std::sqrt(zn * zf)) / sinGamma : INFINITY;
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

double keepFor(const LispsmInput& in) { return 1.0 - std::min(2.0 * std::max(in.marginTexels, 0.0f) / in.size, 0.5); }

void finish(LightView& lv, const glm::dmat4& P, double texelScale, LispsmFit& result, double n, double nOpt,
            double gammaDeg) {
  result.warped = true;
  result.n = float(n), result.nOpt = float(nOpt), result.gammaDeg = float(gammaDeg);
  lv.raster.projection = glm::mat4(P);
  lv.raster.cullSolidsFarSides = false;  // its rays leave the warp's centre, its depth test is the light's depth
  setLightViewRows(lv.gpu.projection, lv.raster.projection);
  lv.gpu.warp = LIGHT_WARP_PERSPECTIVE;
  lv.gpu.texelScale = float(texelScale);
}

LightView fitDirectional(const LispsmInput& in, LispsmFit& result) {
  // The uniform view supplies the light's eye space, its depth range (every caster towards the light: B extruded)
  // and the light's own terms; only the projection and the texel terms change.
  LightView lv = fitLightView(in.light, in.scene, in.size, in.receivers, in.marginTexels);
  const Bounds scene = in.scene.orUnit();
  const glm::dmat4 eye(lv.raster.view);
  const std::vector<glm::dvec2> body = bodyFootprint(in, scene, eye);
  if (body.empty()) return lv;
  const Axes axes = lightSpaceAxes(eye, in.camera);
  const double minExtent = 1e-4 * std::max<double>(scene.radius(), 1e-6);
  Warp warp = bodyRanges(body, axes, minExtent);
  const double nOpt = optimalN(in, axes.sinGamma);
  const glm::dvec2 eyeXY(eye * glm::dvec4(glm::dvec3(in.camera.eye), 1.0));
  placeWarp(warp, body, axes, in.n > 0 ? double(in.n) : nOpt, glm::dot(axes.u, eyeXY));
  const glm::dmat4 P = warpMatrix(warp, axes, lv.gpu.zNear, lv.gpu.zFar, keepFor(in), minExtent);
  double texelMin = INFINITY, texelMax = 0;
  for (const glm::dvec2& p : body) {
    const double texel = texelAt(P, in.size, glm::dvec3(p, 0.0));
    texelMin = std::min(texelMin, texel), texelMax = std::max(texelMax, texel);
  }
  result.texelMin = float(texelMin), result.texelMax = float(texelMax);
  finish(lv, P, std::sqrt(texelMin * texelMax), result, warp.n, nOpt, axes.gammaDeg);  // a typical texel
  return lv;
}

// M = W (P_L V_L) for a spot light: W's rows x, y, w read the post-perspective (x, y, 1) = (x_c, y_c, w_c) / w_c of
// P_L, so their products with P_L's rows x, y, w are linear in light-eye space with no constant term. The z row is
// free (the stored depth is -z_eye, raster/rasterizer.h): z_c = k (d - zNear) - w_c puts the rasterizer's near clip
// z_c >= -w_c exactly on the light's near plane, so nothing behind the light is drawn whatever the sign of w_c.
glm::dmat4 composeSpot(const glm::dmat4& W, const glm::dmat4& PL, double zNear, double k) {
  const glm::dmat4 w = glm::transpose(W), pl = glm::transpose(PL);  // rows
  glm::dvec4 rows[4];
  for (int r : {0, 1, 3}) rows[r] = w[r].x * pl[0] + w[r].y * pl[1] + w[r].w * pl[3];
  rows[2] = k * glm::dvec4(0.0, 0.0, -1.0, -zNear) - rows[3];
  return glm::transpose(glm::dmat4(rows[0], rows[1], rows[2], rows[3]));
}

// The spot's body: B = camera slice ∩ scene box ∩ light frustum (all as planes, so it is clipped to the light's near
// plane before any divide), its vertices in world and light-eye space, and the hull of their post-perspective
// (x, y) = (P_L e).xy / w, where the light is directional along z.
struct SpotBody {
  std::vector<glm::dvec3> world, eye;
  std::vector<glm::dvec2> hull;
  glm::dvec3 centroid{0.0};
};

SpotBody spotBody(const LispsmInput& in, const Bounds& scene, const glm::dmat4& eye, const glm::dmat4& PL, double zNear,
                  double slack) {
  std::vector<Plane> planes = frustumPlanes(in.camera, in.nearDepth, in.farDepth, slack);
  for (const std::vector<Plane>& more : {boxPlanes(scene, slack), clipPlanes(PL * eye, slack)})
    planes.insert(planes.end(), more.begin(), more.end());
  SpotBody b;
  std::vector<glm::dvec2> pps;
  for (const glm::dvec3& p : intersectionPoints(planes)) {
    const glm::dvec4 e = eye * glm::dvec4(p, 1.0), c = PL * e;
    if (!(c.w > 0.5 * zNear)) continue;  // cannot happen beyond the slack: B is inside the near plane
    b.world.push_back(p), b.eye.push_back(glm::dvec3(e)), pps.push_back(glm::dvec2(c) / c.w), b.centroid += p;
  }
  b.hull = convexHull(pps);
  if (!b.world.empty()) b.centroid /= double(b.world.size());
  return b;
}

// Light space for a spot: the camera's central ray is a line in post-perspective space too, its direction there
// P_L's Jacobian applied to the view direction at any of its points in front of the light; take the one nearest
// B's centroid (`at`; the centroid itself if that is not in front). gamma: the world angle between the view and the
// light's ray through `at`, exactly 0 when the view ray runs through the light.
struct SpotAxes {
  Axes axes;
  glm::dvec3 view, ray;
  glm::dvec2 at;  // post-perspective (x, y) of `at`
};

SpotAxes spotAxes(const LispsmInput& in, const SpotBody& body, const glm::dmat4& eye, const glm::dmat4& PL,
                  double zNear) {
  SpotAxes s;
  const glm::dvec3 from(in.camera.eye);
  s.view = glm::normalize(glm::dvec3(in.camera.target - in.camera.eye));
  glm::dvec3 at = from + std::max(glm::dot(body.centroid - from, s.view), double(in.nearDepth)) * s.view;
  if (!((PL * (eye * glm::dvec4(at, 1.0))).w > 0.5 * zNear)) at = body.centroid;
  s.ray = glm::normalize(at - glm::dvec3(in.light.position));
  const double across = glm::length(glm::cross(s.view, s.ray));
  const glm::dvec4 c0 = PL * (eye * glm::dvec4(at, 1.0)), dc = PL * (eye * glm::dvec4(s.view, 0.0));
  s.at = glm::dvec2(c0) / c0.w;
  const glm::dvec2 projected = (glm::dvec2(dc) - s.at * dc.w) / c0.w;
  s.axes = axesAlong(projected, across, glm::degrees(std::atan2(across, glm::dot(s.view, s.ray))));
  return s;
}

// Post-perspective units per world unit of n: B's depth along the warp axis in each space (for a distant spot, nearly
// a sun, the ratio n / depth(B) is then the directional one).
double perWorldUnit(const SpotBody& body, const SpotAxes& s, double depthB, double minWorld) {
  if (!(s.axes.sinGamma > 1e-9)) return depthB / minWorld;  // n is clamped to the uniform limit anyway
  const glm::dvec3 axis = glm::normalize(s.view - glm::dot(s.view, s.ray) * s.ray);
  Extent t;
  for (const glm::dvec3& p : body.world) t.grow(glm::dot(axis, p));
  return depthB / std::max(t.hi - t.lo, minWorld);
}

LightView fitSpot(const LispsmInput& in, LispsmFit& result) {
  LightView lv = fitLightView(in.light, in.scene, in.size, in.receivers, in.marginTexels);
  const LightView uniform = lv;
  const Bounds scene = in.scene.orUnit();
  const double radius = std::max<double>(scene.radius(), 1e-6), zNear = lv.gpu.zNear;
  const glm::dmat4 eye(lv.raster.view), PL(lv.raster.projection);
  const SpotBody body = spotBody(in, scene, eye, PL, zNear, 1e-6 * radius);
  if (body.hull.empty()) return lv;  // B empty (the camera sees nothing of the scene inside the cone): uniform
  const SpotAxes s = spotAxes(in, body, eye, PL, zNear);
  const double minExtent = 2e-4;  // post-perspective B spans at most 2 (the light frustum's [-1, 1]^2)
  Warp warp = bodyRanges(body.hull, s.axes, minExtent);
  const double perWorld = perWorldUnit(body, s, warp.depthB, 1e-4 * radius), nOpt = optimalN(in, s.axes.sinGamma);
  const glm::dvec4 ce = PL * (eye * glm::dvec4(glm::dvec3(in.camera.eye), 1.0));
  const glm::dvec2 anchor = ce.w > 0 ? glm::dvec2(ce) / ce.w : s.at;  // the camera behind the light: its ray
  placeWarp(warp, body.hull, s.axes, (in.n > 0 ? double(in.n) : nOpt) * perWorld, glm::dot(s.axes.u, anchor));
  const glm::dmat4 W = warpMatrix(warp, s.axes, 1.0, 2.0, keepFor(in), minExtent);  // its z row is replaced
  const glm::dmat4 M = composeSpot(W, PL, zNear, warp.n + warp.depthB);
  double texelMin = INFINITY, texelMax = 0, perDepth = 0;
  for (const glm::dvec3& e : body.eye) {
    const double texel = texelAt(M, in.size, e);
    if (!(std::isfinite(texel) && texel > 0 && (M * glm::dvec4(e, 1.0)).w > 0)) return uniform;  // degenerate
    texelMin = std::min(texelMin, texel), texelMax = std::max(texelMax, texel), perDepth += std::log(texel / -e.z);
  }
  result.texelMin = float(texelMin), result.texelMax = float(texelMax);
  finish(lv, M, std::exp(perDepth / double(body.eye.size())), result, warp.n / perWorld, nOpt, s.axes.gammaDeg);
  return lv;
}

}  // namespace

std::string LispsmFit::describe() const {
  if (!warped) return fmt::format("lispsm: {}, uniform map", uniformBecause);
  return fmt::format("lispsm n {:.6g} (n_opt {:.6g}, gamma {:.3g} deg), texel {:.4g}..{:.4g}", n, nOpt, gammaDeg,
                     texelMin, texelMax);
}

LightView fitLispsmView(const LispsmInput& in, LispsmFit* fit) {
  LispsmFit result;
  LightView lv = in.light.type == LightType::Spot ? fitSpot(in, result) : fitDirectional(in, result);
  if (fit != nullptr) *fit = result;
  return lv;
}

}  // namespace penumbra
