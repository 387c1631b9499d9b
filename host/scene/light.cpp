// Spot (optionally disk area), directional (optionally sun disk) and point (optionally sphere) lights: the
// centre axis and the strict parsing and printing of "spot:PX,PY,PZ:TX,TY,TZ:FOV_DEG[:RADIUS]",
// "dir:DX,DY,DZ[:ANG_DEG]" and "point:PX,PY,PZ[:RADIUS]".
#include "host/scene/light.h"

#include <fmt/format.h>

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "host/scene/limits.h"
#include "host/scene/spec_parse.h"

namespace penumbra {
namespace {

constexpr float kMaxAngularRadiusDeg = 45.0f;  // exclusive; a sun disk wider than this is not a "sun"

float parseRadius(std::string_view text) {
  const float radius = detail::parseFiniteFloat(text, "radius");
  if (radius < 0.0f) throw std::invalid_argument(fmt::format("radius: {} is negative", radius));
  // A light larger than the coordinate range has no meaning, and Embree's reference aborts on one (from 1e19).
  if (!inCoordinateRange(radius))
    throw std::invalid_argument(fmt::format("radius: {} is outside [0, 1e+18] (the renderer's coordinate range)", text));
  return radius;
}

Light parseSpot(const std::vector<std::string_view>& parts) {
  if (parts.size() != 4 && parts.size() != 5)
    throw std::invalid_argument("expected spot:PX,PY,PZ:TX,TY,TZ:FOV_DEG[:RADIUS]");
  Light light;
  light.type = LightType::Spot;
  light.position = detail::parseVec3(parts[1], "position");
  light.target = detail::parseVec3(parts[2], "target");
  if (light.position == light.target) throw std::invalid_argument("position equals target");
  light.fovDeg = detail::parseFiniteFloat(parts[3], "fov");
  if (!(light.fovDeg > 0.0f && light.fovDeg < 180.0f))
    throw std::invalid_argument(fmt::format("fov: {} degrees is outside (0, 180)", light.fovDeg));
  if (parts.size() == 5) light.radius = parseRadius(parts[4]);
  return light;
}

Light parsePoint(const std::vector<std::string_view>& parts) {
  if (parts.size() != 2 && parts.size() != 3) throw std::invalid_argument("expected point:PX,PY,PZ[:RADIUS]");
  Light light;
  light.type = LightType::Point;
  light.position = detail::parseVec3(parts[1], "position");
  if (parts.size() == 3) light.radius = parseRadius(parts[2]);
  return light;
}

Light parseDirectional(const std::vector<std::string_view>& parts) {
  if (parts.size() != 2 && parts.size() != 3) throw std::invalid_argument("expected dir:DX,DY,DZ[:ANGULAR_RADIUS_DEG]");
  Light light;
  light.type = LightType::Directional;
  const glm::vec3 d = detail::parseVec3(parts[1], "direction");
  const float len = glm::length(d);
  if (!(len > 0.0f) || !std::isfinite(len)) throw std::invalid_argument("direction: zero or overflowing vector");
  light.direction = d / len;
  if (parts.size() == 3) {
    light.angularRadiusDeg = detail::parseFiniteFloat(parts[2], "angular radius");
    if (!(light.angularRadiusDeg >= 0.0f && light.angularRadiusDeg < kMaxAngularRadiusDeg))
      throw std::invalid_argument(
          fmt::format("angular radius: {} degrees is outside [0, {})", light.angularRadiusDeg, kMaxAngularRadiusDeg));
  }
  return light;
}

}  // namespace

glm::vec3 Light::axis() const {
  if (type == LightType::Point) return {0, -1, 0};
  const glm::vec3 d = type == LightType::Spot ? target - position : direction;
  const float len = glm::length(d);
  return len > 0.0f ? d / len : glm::vec3(0, -1, 0);
}

std::string Light::describe() const {
  if (type == LightType::Spot) {
    std::string s =
        "spot:" + detail::formatVec3(position) + ":" + detail::formatVec3(target) + ":" + detail::formatFloat(fovDeg);
    return radius > 0.0f ? s + ":" + detail::formatFloat(radius) : s;
  }
  if (type == LightType::Point) {
    const std::string s = "point:" + detail::formatVec3(position);
    return radius > 0.0f ? s + ":" + detail::formatFloat(radius) : s;
  }
  std::string s = "dir:" + detail::formatVec3(direction);
  return angularRadiusDeg > 0.0f ? s + ":" + detail::formatFloat(angularRadiusDeg) : s;
}

std::string Light::label() const { return name.empty() ? describe() : "\"" + name + "\""; }

Light parseLight(std::string_view spec) {
  try {
    const auto parts = detail::splitParts(spec, ':');
    if (parts[0] == "spot") return parseSpot(parts);
    if (parts[0] == "dir") return parseDirectional(parts);
    if (parts[0] == "point") return parsePoint(parts);
    throw std::invalid_argument(fmt::format("unknown light type \"{}\" (expected spot, dir or point)", parts[0]));
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(fmt::format("light \"{}\": {}", spec, e.what()));
  }
}

glm::vec2 concentricDisk(glm::vec2 u) {
  const glm::vec2 s = 2.0f * u - 1.0f;
  if (s.x == 0.0f && s.y == 0.0f) return {0.0f, 0.0f};
  constexpr float kQuarter = std::numbers::pi_v<float> / 4.0f;
  float r, phi;
  if (std::abs(s.x) > std::abs(s.y)) {
    r = s.x, phi = kQuarter * (s.y / s.x);
  } else {
    r = s.y, phi = 2.0f * kQuarter - kQuarter * (s.x / s.y);
  }
  return {r * std::cos(phi), r * std::sin(phi)};
}

}  // namespace penumbra
