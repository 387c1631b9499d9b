// Primary rays by Moller-Trumbore in double precision, every triangle for every pixel (test scenes are tiny).
#include "tests/reference/camera_rays_ref.h"

#include <cmath>

#include <glm/glm.hpp>

namespace penumbra::ref {
namespace {

// Ray parameter of the hit, or a negative value for none.
double intersect(const glm::dvec3& o, const glm::dvec3& d, const glm::dvec3& a, const glm::dvec3& b,
                 const glm::dvec3& c) {
  const glm::dvec3 e1 = b - a, e2 = c - a, p = glm::cross(d, e2);
  const double det = glm::dot(e1, p);
  if (std::abs(det) < 1e-300) return -1.0;
  const glm::dvec3 s = o - a;
  const double u = glm::dot(s, p) / det;
  if (u < 0.0 || u > 1.0) return -1.0;
  const glm::dvec3 q = glm::cross(s, e1);
  const double v = glm::dot(d, q) / det;
  if (v < 0.0 || u + v > 1.0) return -1.0;
  return glm::dot(e2, q) / det;
}

}  // namespace

std::vector<int64_t> primaryHits(const Scene& scene, const Camera& camera) {
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
      for (size_t t = 0; t < scene.triangles.size(); ++t) {
        const glm::uvec3 tri = scene.triangles[t];
        const double hit = intersect(origin, dir, glm::dvec3(scene.positions[tri.x]),
                                     glm::dvec3(scene.positions[tri.y]), glm::dvec3(scene.positions[tri.z]));
        const double depth = hit * depthPerT;
        if (hit > 0.0 && hit < best && depth >= camera.clipNear && depth <= camera.clipFar) {
          best = hit;
          hits[static_cast<size_t>(y) * camera.width + x] = static_cast<int64_t>(t);
        }
      }
    }
  return hits;
}

}  // namespace penumbra::ref
