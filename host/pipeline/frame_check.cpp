// Frame input range checks and the empty-frame warning (host/pipeline/frame_check.h).
#include "host/pipeline/frame_check.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "host/scene/limits.h"
#include "raster/constants.h"

namespace penumbra {
namespace {

static_assert(kMaxImageSide == RASTER_MAX_VIEWPORT, "the command line, scene files and the rasterizer share one limit");

bool inRange(const glm::vec3& v) { return inCoordinateRange(v.x, v.y, v.z); }

void check(const glm::vec3& v, const std::string& what) {
  if (!inRange(v))
    throw std::invalid_argument(fmt::format("{} ({}, {}, {}) is outside +-{:g} (the renderer's coordinate range)", what,
                                            v.x, v.y, v.z, kMaxCoordinate));
}

}  // namespace

namespace {

// A view direction from `from` to `to` that float can carry: their distance at least 1e-6 of their magnitude (float
// keeps 7 digits; eye and target 1e-30 apart made the view matrix NaN, reported as the rasterizer's "view or
// projection matrix is not finite" with no option named).
void checkDirection(const glm::vec3& from, const glm::vec3& to, const std::string& what) {
  const glm::dvec3 a(from), b(to);
  const double distance = glm::length(b - a), scale = std::max({1.0, glm::length(a), glm::length(b)});
  if (!(distance >= 1e-6 * scale))
    throw std::invalid_argument(fmt::format("{}: ({}, {}, {}) and ({}, {}, {}) are {:g} apart, too close for a view "
                                            "direction",
                                            what, from.x, from.y, from.z, to.x, to.y, to.z, distance));
}

}  // namespace

void checkFrameRange(const Scene& scene, const Camera& camera, std::span<const Light> lights) {
  if (camera.width < 1 || camera.width > kMaxImageSide || camera.height < 1 || camera.height > kMaxImageSide)
    throw std::invalid_argument(fmt::format("camera size {}x{} is outside 1x1 .. {}x{}", camera.width, camera.height,
                                            kMaxImageSide, kMaxImageSide));
  check(camera.eye, "camera eye"), check(camera.target, "camera target");
  checkDirection(camera.eye, camera.target, "camera eye and target");
  for (const Light& light : lights) {
    if (light.type == LightType::Directional) continue;
    check(light.position, fmt::format("light {}: position", light.label()));
    if (light.type == LightType::Spot) {
      check(light.target, fmt::format("light {}: target", light.label()));
      checkDirection(light.position, light.target, fmt::format("light {}: position and target", light.label()));
    }
  }
  const Bounds bounds = scene.bounds();
  if (bounds.empty()) return;
  check(bounds.min, "the scene's bounds: minimum corner");
  check(bounds.max, "the scene's bounds: maximum corner");
}

namespace {

// Squared distance from p to segment [a, b].
double segmentDistance2(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b) {
  const glm::dvec3 ab = b - a;
  const double length2 = glm::dot(ab, ab);
  const double t = length2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / length2, 0.0, 1.0) : 0.0;
  const glm::dvec3 d = p - (a + t * ab);
  return glm::dot(d, d);
}

// Squared distance from p to triangle abc: to its plane where p projects inside it (every edge's side test agrees
// with the normal), else to the nearest edge; a degenerate triangle is its edges.
double triangleDistance2(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  const glm::dvec3 n = glm::cross(b - a, c - a);
  const double n2 = glm::dot(n, n);
  if (n2 > 0.0) {
    const bool inside = glm::dot(glm::cross(b - a, p - a), n) >= 0.0 && glm::dot(glm::cross(c - b, p - b), n) >= 0.0 &&
                        glm::dot(glm::cross(a - c, p - c), n) >= 0.0;
    if (inside) {
      const double h = glm::dot(p - a, n);
      return h * h / n2;
    }
  }
  return std::min({segmentDistance2(p, a, b), segmentDistance2(p, b, c), segmentDistance2(p, c, a)});
}

}  // namespace

std::optional<std::string> lightReachWarning(const Scene& scene, const Light& light) {
  if (light.type == LightType::Directional || !(light.radius > 0.0f) || scene.triangles.empty()) return std::nullopt;
  const Bounds bounds = scene.bounds();
  const glm::dvec3 p(light.position);
  const glm::dvec3 nearestPoint = glm::clamp(p, glm::dvec3(bounds.min), glm::dvec3(bounds.max));
  const double radius = light.radius, radius2 = radius * radius;
  if (glm::dot(p - nearestPoint, p - nearestPoint) >= radius2) return std::nullopt;  // the bounds lie out of reach
  for (const glm::uvec3& t : scene.triangles) {
    const double d2 = triangleDistance2(p, glm::dvec3(scene.positions[t.x]), glm::dvec3(scene.positions[t.y]),
                                        glm::dvec3(scene.positions[t.z]));
    if (d2 < radius2)
      return fmt::format(
          "light {}: the scene comes within {:g} of its centre, inside its radius {:g}: a surface inside the {} has no "
          "defined visibility, and the shadow maps and `penumbra reference` answer differently there",
          light.label(), std::sqrt(d2), radius, light.type == LightType::Point ? "light's sphere" : "light's disk");
  }
  return std::nullopt;
}

std::optional<std::string> emptyFrameWarning(const Scene& scene, const Camera& camera, std::span<const float> alpha) {
  return emptyFrameWarning(scene, camera, std::any_of(alpha.begin(), alpha.end(), [](float a) { return a > 0.0f; }));
}

std::optional<std::string> emptyFrameWarning(const Scene& scene, const Camera& camera, bool seesSurface) {
  if (seesSurface) return std::nullopt;
  const Bounds bounds = scene.bounds();
  std::string why;
  if (bounds.empty() || bounds.radius() == 0.0f)
    why = "the scene's geometry has no extent (every node scaled to 0?)";
  else if (scene.triangleCount() > 0)
    why = fmt::format(
        "the scene's {} triangles lie within ({}, {}, {}) .. ({}, {}, {}); none is in view or all have "
        "zero area",
        scene.triangleCount(), bounds.min.x, bounds.min.y, bounds.min.z, bounds.max.x, bounds.max.y, bounds.max.z);
  return fmt::format("the frame sees no surface: camera {} ({}x{}) shows only background; {}", camera.describe(),
                     camera.width, camera.height, why);
}

}  // namespace penumbra
