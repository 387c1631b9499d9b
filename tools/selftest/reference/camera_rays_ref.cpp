// Primary rays by Moller-Trumbore in double precision, every triangle for every pixel (test scenes are tiny), with the
// G-buffer's material rules.
#include "tools/selftest/reference/camera_rays_ref.h"

#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>

#include "tools/selftest/reference/alpha_ref.h"
#include "tools/selftest/reference/raster_ref.h"

namespace penumbra::ref {
namespace {

struct Hit {
  double t = -1.0;   // ray parameter, negative for none
  double u = 0, v = 0;  // the hit is (1 - u - v) a + u b + v c
  bool front = true;    // the ray meets the counter-clockwise side
};

Hit intersect(const glm::dvec3& o, const glm::dvec3& d, const glm::dvec3& a, const glm::dvec3& b,
              const glm::dvec3& c) {
  const glm::dvec3 e1 = b - a, e2 = c - a, p = glm::cross(d, e2);
  const double det = glm::dot(e1, p);
  if (std::abs(det) < 1e-300) return {};
  const glm::dvec3 s = o - a;
  const double u = glm::dot(s, p) / det;
  if (u < 0.0 || u > 1.0) return {};
  const glm::dvec3 q = glm::cross(s, e1);
  const double v = glm::dot(d, q) / det;
  if (v < 0.0 || u + v > 1.0) return {};
  return {glm::dot(e2, q) / det, u, v, det > 0};  // det = -d . (e1 x e2)
}

// Whether the hit survives triangle t's material (sidedness, alpha test); marks `border` for undecided alpha.
bool survives(const Scene& scene, size_t t, const Hit& hit, bool& border) {
  const Material* m = scene.materialOf(t);
  if (m == nullptr) return true;
  if (!m->doubleSided && !hit.front) return false;
  if (!m->mayDiscard()) return true;
  const glm::uvec3 tri = scene.triangles[t];
  glm::dvec2 uv[3];
  double largest = 0;
  for (int k = 0; k < 3; ++k) {
    uv[k] = scene.uvs.empty() ? glm::dvec2(0.0) : glm::dvec2(scene.uvs[tri[k]]);
    largest = std::max({largest, std::abs(uv[k].x), std::abs(uv[k].y)});
  }
  const glm::dvec2 at = (1 - hit.u - hit.v) * uv[0] + hit.u * uv[1] + hit.v * uv[2];
  const auto coverage = [&](glm::dvec2 p) {
    return alphaCoverage(*m, scene.alphaTextures, scene.alphaTexels, p.x, p.y);
  };
  const double cutoff = alphaCutoff(*m), slack = test::kUvSlack * (1 + largest);
  const bool keep = coverage(at) >= cutoff;
  border = border || std::abs(coverage(at) - cutoff) < test::kAlphaBorder;
  for (const glm::dvec2 d : {glm::dvec2(slack, 0), glm::dvec2(-slack, 0), glm::dvec2(0, slack), glm::dvec2(0, -slack)})
    border = border || (coverage(at + d) >= cutoff) != keep;
  return keep;
}

}  // namespace

std::vector<int64_t> primaryHits(const Scene& scene, const Camera& camera, std::vector<uint8_t>* alphaBorder) {
  if (alphaBorder) alphaBorder->assign(static_cast<size_t>(camera.width) * camera.height, 0);
  const glm::dvec3 eye(camera.eye), forward = glm::normalize(glm::dvec3(camera.target) - eye);
  const glm::dvec3 right = glm::normalize(glm::cross(forward, glm::dvec3(camera.up)));
  const glm::dvec3 up = glm::cross(right, forward);
  const double aspect = double(camera.width) / camera.height;
  const double halfY =
      camera.orthographic() ? camera.orthoHalfHeight : std::tan(glm::radians(double(camera.fovYDeg)) / 2);
  std::vector<int64_t> hits(static_cast<size_t>(camera.width) * camera.height, kNoHit);
  for (int y = 0; y < camera.height; ++y)
    for (int x = 0; x < camera.width; ++x) {
      const double sx = (2.0 * (x + 0.5) / camera.width - 1.0) * halfY * aspect;
      const double sy = (2.0 * (y + 0.5) / camera.height - 1.0) * halfY;
      glm::dvec3 origin = eye, dir = forward;
      if (camera.orthographic())
        origin += sx * right + sy * up;
      else
        dir = glm::normalize(forward + sx * right + sy * up);
      const double depthPerT = glm::dot(dir, forward);  // view depth per unit of t
      double best = INFINITY;
      bool border = false;
      for (size_t t = 0; t < scene.triangles.size(); ++t) {
        const glm::uvec3 tri = scene.triangles[t];
        const Hit hit = intersect(origin, dir, glm::dvec3(scene.positions[tri.x]), glm::dvec3(scene.positions[tri.y]),
                                  glm::dvec3(scene.positions[tri.z]));
        const double depth = hit.t * depthPerT;
        if (hit.t > 0.0 && hit.t < best && depth >= camera.clipNear && depth <= camera.clipFar &&
            survives(scene, t, hit, border)) {
          best = hit.t;
          hits[static_cast<size_t>(y) * camera.width + x] = static_cast<int64_t>(t);
        }
      }
      if (alphaBorder) (*alphaBorder)[static_cast<size_t>(y) * camera.width + x] = border;
    }
  return hits;
}

}  // namespace penumbra::ref
