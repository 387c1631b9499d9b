// Cameras, lights and placements of scene files, with the same ranges as the command-line forms
// (camera.h, light.h): fields outside them are refused with the field's JSON pointer.
#include "host/scene/scene_file_parts.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include "host/scene/light_names.h"
#include "host/scene/limits.h"

namespace penumbra::detail {
namespace {

void readSize(ObjectReader& r, Camera& camera) {
  const Json* size = r.find("size");
  if (!size) return;
  const bool ok = size->is_array() && size->size() == 2 && (*size)[0].is_number_integer() &&
                  (*size)[1].is_number_integer() && (*size)[0].get<int64_t>() >= 1 && (*size)[1].get<int64_t>() >= 1 &&
                  (*size)[0].get<int64_t>() <= kMaxImageSide && (*size)[1].get<int64_t>() <= kMaxImageSide;
  if (!ok)
    r.fail("size", fmt::format("expected [width, height], integers in 1..{}, got {}", kMaxImageSide, brief(*size)));
  camera.width = static_cast<int>((*size)[0].get<int64_t>());
  camera.height = static_cast<int>((*size)[1].get<int64_t>());
}

glm::vec3 nonZero(ObjectReader& r, const char* key) {
  const glm::vec3 v = r.vec3(key);
  if (!(glm::length(v) > 0.0f)) r.fail(key, "must not be the zero vector");
  return v;
}

}  // namespace

Camera readCamera(const Json& value, const std::string& file, const std::string& pointer) {
  ObjectReader r(value, file, pointer);
  Camera camera;
  camera.eye = r.vec3("eye");
  camera.target = r.vec3("target");
  if (camera.eye == camera.target) r.fail("target", "equals eye");
  camera.fovYDeg = static_cast<float>(r.number("fovy_deg", 0, 180, "(0, 180)", 45.0));
  readSize(r, camera);
  r.finish();
  return camera;
}

namespace {

// "technique": "pcss" and "params": {"light-size": 2, "filter": "poisson"}: kept as text (numbers as JSON writes
// them, booleans as on/off); the tools check the name and the values against the technique registry.
void readLightTechnique(ObjectReader& r, Light& light) {
  if (r.has("technique")) {
    light.technique = r.string("technique");
    if (light.technique.empty()) r.fail("technique", "is empty");
  }
  const Json* params = r.find("params");
  if (params == nullptr) return;
  if (light.technique.empty()) r.fail("params", "needs \"technique\" beside it");
  if (!params->is_object()) r.fail("params", fmt::format("expected an object, got {}", brief(*params)));
  for (const auto& [name, value] : params->items()) {
    const std::string pointer = pointerTo(r.pointer("params"), name);
    if (value.is_string())
      light.params[name] = value.get<std::string>();
    else if (value.is_boolean())
      light.params[name] = value.get<bool>() ? "on" : "off";
    else if (value.is_number() && std::isfinite(value.get<double>()))
      light.params[name] = value.dump();
    else
      failAt(r.file(), pointer, fmt::format("expected a number, a string or a boolean, got {}", brief(value)));
  }
}

}  // namespace

Light readLight(const Json& value, const std::string& file, const std::string& pointer) {
  ObjectReader r(value, file, pointer);
  Light light;
  if (r.has("name")) light.name = r.string("name");
  const std::string type = r.string("type");
  if (type == "spot") {
    light.type = LightType::Spot;
    light.position = r.vec3("position");
    light.target = r.vec3("target");
    if (light.position == light.target) r.fail("target", "equals position");
    light.fovDeg = static_cast<float>(r.number("fov_deg", 0, 180, "(0, 180)", 60.0));
    light.radius = static_cast<float>(r.number("radius", 0, kMaxCoordinate, "[0, 1e+18] (the renderer's coordinate range)", 0.0));
  } else if (type == "dir") {
    light.type = LightType::Directional;
    light.direction = glm::normalize(nonZero(r, "direction"));
    light.angularRadiusDeg = static_cast<float>(r.number("angular_radius_deg", 0, 45, "[0, 45)", 0.0));
  } else if (type == "point") {
    light.type = LightType::Point;
    light.position = r.vec3("position");
    light.radius = static_cast<float>(r.number("radius", 0, kMaxCoordinate, "[0, 1e+18] (the renderer's coordinate range)", 0.0));
  } else {
    r.fail("type", fmt::format("expected \"spot\", \"dir\" or \"point\", got \"{}\"", type));
  }
  readLightTechnique(r, light);
  r.finish();
  return light;
}

void readLightSize(const Json& value, const std::string& file, const std::string& pointer, std::vector<Light>& lights) {
  ObjectReader r(value, file, pointer);
  const std::string name = r.string("name");
  const auto it = std::find_if(lights.begin(), lights.end(), [&](const Light& l) { return l.name == name; });
  if (it == lights.end())
    r.fail("name", fmt::format("no light named \"{}\" in the models (their lights: {}); give \"type\" to define a "
                               "new light",
                               name, listLights(lights)));
  if (it->type == LightType::Directional) {
    if (r.has("radius")) r.fail("radius", fmt::format("light \"{}\" is directional: give angular_radius_deg", name));
    it->angularRadiusDeg = static_cast<float>(r.number("angular_radius_deg", 0, 45, "[0, 45)"));
  } else {
    if (r.has("angular_radius_deg"))
      r.fail("angular_radius_deg", fmt::format("light \"{}\" is not directional: give radius", name));
    it->radius =
        static_cast<float>(r.number("radius", 0, kMaxCoordinate, "[0, 1e+18] (the renderer's coordinate range)"));
  }
  r.finish();
}

glm::mat4 readPlacement(ObjectReader& r) {
  glm::dmat4 m(1.0);
  if (auto t = r.optionalVec3("translation")) m = glm::translate(m, glm::dvec3(*t));
  if (r.has("rotation_deg") && r.has("rotation_quat"))
    r.fail("rotation_quat", "give rotation_deg or rotation_quat, not both");
  if (auto euler = r.optionalVec3("rotation_deg")) {
    const glm::dvec3 rad = glm::radians(glm::dvec3(*euler));
    m = glm::rotate(m, rad.z, glm::dvec3(0, 0, 1));
    m = glm::rotate(m, rad.y, glm::dvec3(0, 1, 0));
    m = glm::rotate(m, rad.x, glm::dvec3(1, 0, 0));
  }
  if (const Json* q = r.find("rotation_quat")) {
    const glm::dvec4 v = numberArray(*q, 4, r.file(), r.pointer("rotation_quat"));
    if (!(glm::length(v) > 0.0)) r.fail("rotation_quat", "must not be the zero quaternion");
    m *= glm::mat4_cast(glm::dquat(v.w, v.x, v.y, v.z) / glm::length(v));
  }
  if (const Json* s = r.find("scale")) {
    const glm::dvec3 scale =
        s->is_number() ? glm::dvec3(s->get<double>()) : glm::dvec3(numberArray(*s, 3, r.file(), r.pointer("scale")));
    if (!std::isfinite(scale.x) || scale.x * scale.y * scale.z == 0.0)
      r.fail("scale", "expected a non-zero finite number or 3 non-zero finite numbers, got " + brief(*s));
    m = glm::scale(m, scale);
  }
  return glm::mat4(m);
}

}  // namespace penumbra::detail
