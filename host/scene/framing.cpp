// Framing: distances come from the bounding sphere, d = r / sin(half the narrower field of view), so the
// whole sphere is inside the frustum whatever the view direction.
#include "host/scene/framing.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace penumbra {
namespace {

constexpr float kFramingMargin = 1.15f;  // 15% free space around the bounding sphere
constexpr float kLightReach = 2.0f;      // the cone covers twice the bounding radius: model and shadow

float safeRadius(const Bounds& b) {
  if (b.empty()) throw std::invalid_argument("framing: empty bounds");
  return std::max(b.radius(), 1e-6f);
}

}  // namespace

Camera framingCamera(const Bounds& bounds, int width, int height, float fovYDeg) {
  Camera c;
  c.width = width, c.height = height, c.fovYDeg = fovYDeg;
  const float r = safeRadius(bounds);
  const float halfY = glm::radians(fovYDeg) / 2;
  const float halfX = std::atan(std::tan(halfY) * c.aspect());
  const float distance = kFramingMargin * r / std::sin(std::min(halfX, halfY));
  c.target = bounds.center();
  c.eye = c.target + glm::normalize(glm::vec3(1.0f, 0.7f, 1.4f)) * distance;
  return c;
}

Light framingLight(const Bounds& bounds) {
  const float r = safeRadius(bounds);
  Light l;
  l.type = LightType::Spot;
  l.target = glm::vec3(bounds.center().x, bounds.min.y, bounds.center().z);
  const float distance = 4.0f * r;
  l.position = l.target + glm::normalize(glm::vec3(-0.5f, 1.6f, 0.4f)) * distance;
  l.fovDeg = 2.0f * glm::degrees(std::atan(kLightReach * r / distance));
  l.radius = 0.05f * r;
  return l;
}

}  // namespace penumbra
