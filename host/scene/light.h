// Lights that cast the shadows we filter: spot lights (optionally disk area lights), directional lights
// (optionally sun disks with an angular radius) and point lights (optionally sphere lights; shadowed as six cube
// faces, host/pipeline/point_light.h), and their command-line form.
#pragma once

#include <map>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

namespace penumbra {

enum class LightType { Spot, Directional, Point };

struct Light {
  LightType type = LightType::Spot;
  // Who the light is: a glTF light's (or its node's) name, a scene file's "name", or empty for a light given
  // on the command line or by a framing default. Loaders make the names of a scene's lights unique and
  // channel-safe (light_names.h).
  std::string name;
  // Spot: a light at `position` aiming at `target` with a full cone angle `fovDeg`. radius > 0 makes it a
  // disk area light of that radius centred at position, facing target. Point: a light at `position` shining
  // every way; radius > 0 makes it a sphere light of that radius.
  glm::vec3 position{0, 10, 0};
  glm::vec3 target{0, 0, 0};
  float fovDeg = 60.0f;
  float radius = 0.0f;
  // Spot: the full angle of the fully lit inner cone (glTF 2 x innerConeAngle): the preview falls off between it and
  // fovDeg as KHR_lights_punctual prescribes (kernels/shade.cl); negative: the preview's own falloff (the command
  // line's spots). Visibility never depends on it.
  float innerFovDeg = -1.0f;
  // Spot and point: glTF's range in metres beyond which the light does not reach; 0: unlimited. The preview fades
  // the light out towards it (kernels/shade.cl); visibility never depends on it.
  float range = 0.0f;
  // Directional: `direction` is the direction the light travels (unit length). angularRadiusDeg > 0 makes
  // it a sun disk of that angular radius.
  glm::vec3 direction{0, -1, 0};
  float angularRadiusDeg = 0.0f;
  // A scene file's per-light shadow technique ("technique", "params"): empty = the command line's. The scene layer
  // keeps them as text; the tools check them against the technique registry (an unknown name or value: exit 2).
  std::string technique;
  std::map<std::string, std::string> params;  // parameter name (no dashes) -> value as text

  bool isArea() const { return type == LightType::Directional ? angularRadiusDeg > 0 : radius > 0; }
  glm::vec3 axis() const;        // unit direction light travels along its centre axis ((0, -1, 0) for points)
  std::string describe() const;  // the command-line form, for EXR provenance
  std::string label() const;     // for messages: "\"NAME\"" when named, else the command-line form
};

// "spot:PX,PY,PZ:TX,TY,TZ:FOV_DEG[:RADIUS]", "dir:DX,DY,DZ[:ANGULAR_RADIUS_DEG]" or "point:PX,PY,PZ[:RADIUS]".
// Throws std::invalid_argument naming the bad part: non-finite numbers, zero direction, P == T, fov outside
// (0, 180), negative radius, angular radius outside [0, 45).
Light parseLight(std::string_view spec);

// Shirley & Chiu's concentric map ("A Low Distortion Map Between Disk and Square", JGT 1997): [0,1]^2 onto the unit
// disk, area-preserving and continuous, so a stratified square stays a stratified disk. Area lights are sampled
// through it (the reference's sampler, izb's light pattern).
glm::vec2 concentricDisk(glm::vec2 u);

}  // namespace penumbra
