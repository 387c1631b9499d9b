// The pinhole camera: view and projection matrices (glm, OpenGL conventions) and the strict parsing of
// its command-line forms "EX,EY,EZ:TX,TY,TZ[:FOVY_DEG]" and "WxH".
#include "host/scene/camera.h"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>

#include "host/scene/limits.h"
#include "host/scene/spec_parse.h"

namespace penumbra {
namespace {

// sin of the smallest angle between forward and up that lookAt still handles well (~0.06 degrees).
constexpr float kMinUpSine = 1e-3f;

bool usableUp(const glm::vec3& forward, const glm::vec3& up) {
  const float len = glm::length(up);
  if (!(len > 0.0f) || !std::isfinite(len)) return false;
  return glm::length(glm::cross(forward, up / len)) > kMinUpSine;
}

void checkFov(float fovDeg, std::string_view what) {
  if (!(fovDeg > 0.0f && fovDeg < 180.0f))
    throw std::invalid_argument(fmt::format("{}: {} degrees is outside (0, 180)", what, fovDeg));
}

}  // namespace

glm::vec3 chooseUp(const glm::vec3& forward, const glm::vec3& preferred) {
  const glm::vec3 f = glm::normalize(forward);
  for (const glm::vec3& up : {preferred, glm::vec3(0, 0, 1), glm::vec3(1, 0, 0)})
    if (usableUp(f, up)) return glm::normalize(up);
  return glm::vec3(0, 1, 0);  // forward is zero or not finite: nothing is usable
}

glm::mat4 Camera::view() const {
  if (eye == target) throw std::invalid_argument("camera: eye equals target");
  return glm::lookAt(eye, target, chooseUp(target - eye, up));
}

glm::vec2 Camera::halfExtentAt(float depth) const {
  const float halfY = orthographic() ? orthoHalfHeight : std::tan(glm::radians(fovYDeg) * 0.5f) * depth;
  return {halfY * aspect(), halfY};
}

glm::mat4 Camera::projection(float zNear, float zFar) const {
  const bool nearOk = orthographic() ? zNear >= 0.0f : zNear > 0.0f;
  if (!(nearOk && zFar > zNear && std::isfinite(zFar)))
    throw std::invalid_argument(fmt::format("camera: bad depth range near {} far {}", zNear, zFar));
  if (width < 1 || height < 1) throw std::invalid_argument(fmt::format("camera: bad image size {}x{}", width, height));
  if (orthographic()) {
    if (!(orthoHalfHeight > 0.0f && std::isfinite(orthoHalfHeight)))
      throw std::invalid_argument(fmt::format("camera: orthographic half height {} is not positive", orthoHalfHeight));
    const glm::vec2 half = halfExtentAt(0.0f);
    return glm::ortho(-half.x, half.x, -half.y, half.y, zNear, zFar);
  }
  checkFov(fovYDeg, "camera: fovy");
  return glm::perspective(glm::radians(fovYDeg), aspect(), zNear, zFar);
}

std::string Camera::describe() const {
  std::string s = detail::formatVec3(eye) + ":" + detail::formatVec3(target) + ":";
  s += orthographic() ? "ortho=" + detail::formatFloat(orthoHalfHeight) : detail::formatFloat(fovYDeg);
  if (up != glm::vec3(0, 1, 0)) s += ":up=" + detail::formatVec3(up);
  if (clipNear > 0.0f) s += ":near=" + detail::formatFloat(clipNear);
  if (std::isfinite(clipFar)) s += ":far=" + detail::formatFloat(clipFar);
  return s;
}

std::string Camera::label() const {
  if (gltfIndex < 0) return {};
  return fmt::format("gltf:{} \"{}\" ({})", gltfIndex, name, orthographic() ? "orthographic" : "perspective");
}

Camera parseCamera(std::string_view spec) {
  try {
    const auto parts = detail::splitParts(spec, ':');
    if (parts.size() != 2 && parts.size() != 3) throw std::invalid_argument("expected EX,EY,EZ:TX,TY,TZ[:FOVY_DEG]");
    Camera camera;
    camera.eye = detail::parseVec3(parts[0], "eye");
    camera.target = detail::parseVec3(parts[1], "target");
    if (camera.eye == camera.target) throw std::invalid_argument("eye equals target");
    if (parts.size() == 3) {
      camera.fovYDeg = detail::parseFiniteFloat(parts[2], "fovy");
      checkFov(camera.fovYDeg, "fovy");
    }
    return camera;
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(fmt::format("camera \"{}\": {}", spec, e.what()));
  }
}

void parseSize(std::string_view spec, int& width, int& height) {
  const auto parts = detail::splitParts(spec, 'x');
  if (parts.size() != 2) throw std::invalid_argument(fmt::format("size \"{}\": expected WxH, e.g. 1280x720", spec));
  const char* names[2] = {"width", "height"};
  int values[2];
  for (int i = 0; i < 2; ++i) {
    long long v;
    try {
      v = detail::parseInteger(parts[i], names[i]);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(fmt::format("size \"{}\": {}", spec, e.what()));
    }
    if (v < 1 || v > kMaxImageSide)
      throw std::invalid_argument(fmt::format("size \"{}\": {} {} is outside 1..{}", spec, names[i], v, kMaxImageSide));
    values[i] = static_cast<int>(v);
  }
  width = values[0];
  height = values[1];
}

}  // namespace penumbra
