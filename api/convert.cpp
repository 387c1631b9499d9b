// pn_camera / pn_light <-> Camera / Light, field by field.
#include "api/convert.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>

#include "api/guard.h"
#include "host/scene/limits.h"

namespace penumbra::api {
namespace {

void toC(const glm::vec3& v, float out[3]) { out[0] = v.x, out[1] = v.y, out[2] = v.z; }
glm::vec3 fromC(const float v[3]) { return {v[0], v[1], v[2]}; }

// Copies `value` into the caller's struct, keeping its size and writing no byte past it.
template <class Struct>
void fillSized(Struct value, Struct* out, const char* function, const char* name, const char* init) {
  requireSized(out, sizeof(Struct), function, name, init);
  value.size = out->size;
  std::memcpy(static_cast<void*>(out), &value, std::min(out->size, sizeof(Struct)));
}

}  // namespace

pn_camera toC(const Camera& camera) {
  pn_camera c;
  c.size = sizeof(pn_camera);
  toC(camera.eye, c.eye);
  toC(camera.target, c.target);
  toC(camera.up, c.up);
  c.orthographic = camera.orthographic() ? 1 : 0;
  c.fov_y_deg = camera.fovYDeg;
  c.ortho_half_height = camera.orthoHalfHeight;
  c.clip_near = camera.clipNear;
  c.clip_far = camera.clipFar;
  c.width = camera.width;
  c.height = camera.height;
  return c;
}

void fill(const Camera& camera, pn_camera* out, const char* function, const char* name) {
  fillSized(toC(camera), out, function, name, "pn_camera_init");
}

Camera fromC(const pn_camera& c, const char* function, const char* name) {
  requireSized(&c, sizeof(pn_camera), function, name, "pn_camera_init");
  if (c.width < 1 || c.height < 1 || c.width > kMaxImageSide || c.height > kMaxImageSide)
    throw std::invalid_argument(
        fmt::format("camera: size {}x{} outside 1..{} (the rasterizer's limit)", c.width, c.height, kMaxImageSide));
  Camera camera;
  camera.eye = fromC(c.eye);
  camera.target = fromC(c.target);
  camera.up = fromC(c.up);
  camera.kind = c.orthographic != 0 ? ProjectionKind::kOrthographic : ProjectionKind::kPerspective;
  camera.fovYDeg = c.fov_y_deg;
  camera.orthoHalfHeight = c.ortho_half_height;
  camera.clipNear = c.clip_near;
  camera.clipFar = c.clip_far;
  camera.width = c.width;
  camera.height = c.height;
  return camera;
}

pn_light toC(const Light& light) {
  pn_light l;
  l.size = sizeof(pn_light);
  l.type = light.type == LightType::Spot          ? PN_LIGHT_SPOT
           : light.type == LightType::Directional ? PN_LIGHT_DIRECTIONAL
                                                  : PN_LIGHT_POINT;
  l.name = light.name.c_str();
  toC(light.position, l.position);
  toC(light.target, l.target);
  l.fov_deg = light.fovDeg;
  l.radius = light.radius;
  l.inner_fov_deg = light.innerFovDeg;
  l.range = light.range;
  toC(light.direction, l.direction);
  l.angular_radius_deg = light.angularRadiusDeg;
  return l;
}

void fill(const Light& light, pn_light* out, const char* function, const char* name) {
  fillSized(toC(light), out, function, name, "pn_light_init");
}

Light fromC(const pn_light& l, const char* function, const char* name) {
  requireSized(&l, sizeof(pn_light), function, name, "pn_light_init");
  Light light;
  switch (l.type) {
    case PN_LIGHT_SPOT:
      light.type = LightType::Spot;
      break;
    case PN_LIGHT_DIRECTIONAL:
      light.type = LightType::Directional;
      break;
    case PN_LIGHT_POINT:
      light.type = LightType::Point;
      break;
    default:
      throw std::invalid_argument(fmt::format("light: unknown type {}", static_cast<int>(l.type)));
  }
  light.name = l.name != nullptr ? l.name : "";
  light.position = fromC(l.position);
  light.target = fromC(l.target);
  light.fovDeg = l.fov_deg;
  light.radius = l.radius;
  light.innerFovDeg = l.inner_fov_deg;
  light.range = l.range;
  light.direction = fromC(l.direction);
  light.angularRadiusDeg = l.angular_radius_deg;
  return light;
}

}  // namespace penumbra::api
