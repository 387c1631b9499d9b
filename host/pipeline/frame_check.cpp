// Frame input range checks and the empty-frame warning (host/pipeline/frame_check.h).
#include "host/pipeline/frame_check.h"

#include <fmt/format.h>

#include <algorithm>
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
