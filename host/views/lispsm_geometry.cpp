// Convex geometry for LiSPSM's body: plane sets, Liang-Barsky edge clipping, vertex enumeration, 2D hull and cut.
#include "host/views/lispsm_geometry.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "host/views/splits.h"

namespace penumbra::lispsm {
namespace {

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

double cross(const glm::dvec2& o, const glm::dvec2& a, const glm::dvec2& b) {
  return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

}  // namespace

std::vector<Plane> frustumPlanes(const Camera& camera, double near, double far, double slack) {
  // Frustum planes in camera eye space (depth v = -z), carried to world space: f_world(p) = f_eye(V p).
  const glm::dmat4 view(camera.view());
  const glm::dvec2 half(camera.halfExtentAt(1.0f));  // tangents for a pinhole, half extents for ortho
  const double tx = half.x, ty = half.y;
  const bool ortho = camera.orthographic();
  // Side planes: |x| <= tx v for a pinhole (through the eye), |x| <= tx for ortho (parallel to the axis).
  const Plane eyePlanes[6] = {{0, 0, -1, -near},
                              {0, 0, 1, far},
                              ortho ? Plane{-1, 0, 0, tx} : Plane{-1, 0, -tx, 0},
                              ortho ? Plane{1, 0, 0, tx} : Plane{1, 0, -tx, 0},
                              ortho ? Plane{0, -1, 0, ty} : Plane{0, -1, -ty, 0},
                              ortho ? Plane{0, 1, 0, ty} : Plane{0, 1, -ty, 0}};
  std::vector<Plane> planes;
  for (const Plane& e : eyePlanes) {
    Plane w = e * view;  // row vector times matrix
    w.w += slack * glm::length(glm::dvec3(w));
    planes.push_back(w);
  }
  return planes;
}

std::vector<Plane> boxPlanes(const Bounds& box, double slack) {
  std::vector<Plane> planes;
  for (int axis = 0; axis < 3; ++axis) {
    glm::dvec3 n(0.0);
    n[axis] = 1.0;
    planes.push_back(Plane(n, -double(box.min[axis]) + slack));
    planes.push_back(Plane(-n, double(box.max[axis]) + slack));
  }
  return planes;
}

std::vector<Plane> clipPlanes(const glm::dmat4& clip, double slack) {
  const glm::dmat4 t = glm::transpose(clip);  // t[r]: row r of the clip matrix
  std::vector<Plane> planes;
  for (int r = 0; r < 3; ++r)
    for (double sign : {1.0, -1.0}) {
      Plane p = t[3] + sign * t[r];
      const double length = glm::length(glm::dvec3(p));
      if (!(length > 0)) continue;
      p /= length;
      p.w += slack;
      planes.push_back(p);
    }
  return planes;
}

std::vector<glm::dvec3> frustumBoxPoints(const Camera& camera, double near, double far, const Bounds& box,
                                         double slack) {
  const std::vector<glm::vec3> fc = frustumSliceCorners(camera, float(near), float(far));  // bits: x, y, far
  std::array<glm::dvec3, 8> frustum, corners;
  for (int i = 0; i < 8; ++i) {
    frustum[i] = glm::dvec3(fc[i]);
    corners[i] = {i & 1 ? box.max.x : box.min.x, i & 2 ? box.max.y : box.min.y, i & 4 ? box.max.z : box.min.z};
  }
  std::vector<glm::dvec3> points;
  clipEdges(frustum, boxPlanes(box, slack), points);
  clipEdges(corners, frustumPlanes(camera, near, far, slack), points);
  return points;
}

std::vector<glm::dvec3> intersectionPoints(const std::vector<Plane>& planes) {
  std::vector<glm::dvec3> points;
  const size_t m = planes.size();
  for (size_t i = 0; i < m; ++i)
    for (size_t j = i + 1; j < m; ++j)
      for (size_t k = j + 1; k < m; ++k) {
        // Solve A p = -w by Cramer's rule; a near-singular triple (two planes almost parallel) meets nowhere useful.
        const glm::dvec3 a(planes[i]), b(planes[j]), c(planes[k]);
        const glm::dvec3 bc = glm::cross(b, c), ca = glm::cross(c, a), ab = glm::cross(a, b);
        const double det = glm::dot(a, bc);
        const double scale = glm::length(a) * glm::length(b) * glm::length(c);
        if (!(std::abs(det) > 1e-12 * scale)) continue;
        const glm::dvec3 p = -(planes[i].w * bc + planes[j].w * ca + planes[k].w * ab) / det;
        bool inside = std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
        for (size_t q = 0; q < m && inside; ++q) {
          const double f = glm::dot(glm::dvec3(planes[q]), p) + planes[q].w;
          inside = f >= -1e-9 * (glm::length(glm::dvec3(planes[q])) * glm::length(p) + std::abs(planes[q].w));
        }
        if (inside) points.push_back(p);
      }
  return points;
}

std::vector<glm::dvec2> convexHull(std::vector<glm::dvec2> p) {
  std::sort(p.begin(), p.end(),
            [](const glm::dvec2& a, const glm::dvec2& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
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

}  // namespace penumbra::lispsm
