// KHR_lights_punctual import. The schema check (gltf_schema.cpp) has already refused mistyped properties and
// node light indices out of range, so what tinygltf 2.7 kept (model.lights; the node's reference only as
// node.extensions["KHR_lights_punctual"]["light"]) is what the file says; here the values and world transforms.
#include "host/scene/gltf_lights.h"

#include <cmath>
#include <numbers>
#include <optional>
#include <string>

#include <fmt/format.h>

#include "host/scene/light_names.h"
#include "host/scene/limits.h"

namespace penumbra::detail {
namespace {

constexpr double kMaxAngularRadiusDeg = 45.0;  // exclusive, as for dir:...:ANG on the command line

// The light index node `node` references, if any (its range was checked by the schema).
std::optional<int> nodeLight(const tinygltf::Node& node) {
  const auto it = node.extensions.find("KHR_lights_punctual");
  if (it == node.extensions.end()) return std::nullopt;
  const tinygltf::Value& light = it->second.Get("light");
  if (!light.IsNumber()) return std::nullopt;
  return light.GetNumberAsInt();
}

struct Where {
  const GltfContext& ctx;
  std::string what;  // "light 2 \"Key\" (node 5)"
  [[noreturn]] void fail(const std::string& message) const { failGltf(ctx, what + ": " + message); }
};

// extras.penumbra: {"radius": R} for spot and point lights, {"angular_radius_deg": A} for directional ones.
void readSize(const Where& where, const tinygltf::Value& extras, Light& light) {
  if (!extras.IsObject() || !extras.Has("penumbra")) return;
  const tinygltf::Value& size = extras.Get("penumbra");
  if (!size.IsObject()) where.fail("extras.penumbra: expected an object");
  const bool directional = light.type == LightType::Directional;
  const char* key = directional ? "angular_radius_deg" : "radius";
  for (const std::string& k : size.Keys())
    if (k != key)
      where.fail(fmt::format("extras.penumbra.{}: unknown key (a {} light takes only \"{}\")", k,
                             directional ? "directional" : "spot or point", key));
  if (!size.Has(key)) return;
  const tinygltf::Value& v = size.Get(key);
  const double x = v.IsNumber() ? v.GetNumberAsDouble() : NAN;
  const bool ok = directional ? (x >= 0.0 && x < kMaxAngularRadiusDeg) : (x >= 0.0 && x <= kMaxCoordinate);
  if (!ok)
    where.fail(fmt::format("extras.penumbra.{}: expected a number in {}", key,
                           directional ? "[0, 45) degrees" : "[0, 1e+18] metres (the renderer's coordinate range)"));
  (directional ? light.angularRadiusDeg : light.radius) = static_cast<float>(x);
}

void readCone(const Where& where, const tinygltf::SpotLight& spot, Light& light) {
  const double inner = spot.innerConeAngle, outer = spot.outerConeAngle;
  if (!(inner >= 0.0 && inner < outer && outer <= std::numbers::pi / 2))
    where.fail(
        fmt::format("spot cone angles must satisfy 0 <= innerConeAngle < outerConeAngle <= pi/2 (got {} "
                    "and {})",
                    inner, outer));
  if (outer == std::numbers::pi / 2)
    where.fail(
        "outerConeAngle pi/2 (a hemisphere) is not supported yet: a spot's shadow map needs a cone narrower "
        "than 180 degrees");
  light.fovDeg = static_cast<float>(2.0 * outer * 180.0 / std::numbers::pi);
  light.innerFovDeg = static_cast<float>(2.0 * inner * 180.0 / std::numbers::pi);
}

// Position and unit direction (the node's -Z) in world space; throws when the transform collapses or overflows.
void place(const Where& where, const glm::dmat4& world, Light& light) {
  const glm::dvec3 position(world[3]);
  const glm::dvec3 axis = -glm::dvec3(world[2]);
  const double length = glm::length(axis);
  if (!std::isfinite(position.x) || !std::isfinite(position.y) || !std::isfinite(position.z))
    where.fail("the node's world position is not finite");
  if (!(length > 0.0) || !std::isfinite(length))
    where.fail("the node's world transform leaves the light no direction (zero scale, or not finite)");
  const glm::dvec3 direction = axis / length;
  light.position = glm::vec3(position);
  light.direction = glm::vec3(direction);
  light.target = glm::vec3(position + direction);
  if (light.type == LightType::Spot && light.target == light.position)
    where.fail("the light is too far from the origin for a float target one metre along its axis");
}

Light readGltfLight(const GltfContext& ctx, const NodeInstance& inst, int index) {
  const tinygltf::Light& src = ctx.model.lights[static_cast<size_t>(index)];
  const tinygltf::Node& node = ctx.model.nodes[static_cast<size_t>(inst.node)];
  const Where where{
      ctx, fmt::format("light {}{} (node {})", index, src.name.empty() ? "" : " \"" + src.name + "\"", inst.node)};
  Light light;
  if (src.type == "spot")
    light.type = LightType::Spot, readCone(where, src.spot, light);
  else if (src.type == "directional")
    light.type = LightType::Directional;
  else if (src.type == "point")
    light.type = LightType::Point;
  else
    where.fail(fmt::format("type \"{}\" is not one of \"spot\", \"directional\", \"point\"", src.type));
  if (light.type != LightType::Directional) light.range = static_cast<float>(src.range);
  place(where, inst.world, light);
  readSize(where, src.extras, light);
  light.name = !src.name.empty() ? src.name : !node.name.empty() ? node.name : fmt::format("light{}", index);
  return light;
}

}  // namespace

std::vector<Light> readLights(const GltfContext& ctx, const std::vector<NodeInstance>& instances) {
  std::vector<Light> lights;
  for (const NodeInstance& inst : instances) {
    const std::optional<int> index = nodeLight(ctx.model.nodes[static_cast<size_t>(inst.node)]);
    if (!index) continue;
    if (*index < 0 || static_cast<size_t>(*index) >= ctx.model.lights.size())
      failGltf(ctx, fmt::format("node {}: light {} does not exist (the file has {})", inst.node, *index,
                                ctx.model.lights.size()));
    lights.push_back(readGltfLight(ctx, inst, *index));
  }
  nameLights(lights);
  return lights;
}

}  // namespace penumbra::detail
