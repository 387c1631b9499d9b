// Lights that cast the shadows we filter: spot lights (optionally disk area lights) and directional
// lights (optionally sun disks with an angular radius), and their command-line form.
#pragma once

#include <string>
#include <string_view>

#include <glm/glm.hpp>

namespace penumbra {

enum class LightType { Spot, Directional };

struct Light {
  LightType type = LightType::Spot;
  // Spot: a light at `position` aiming at `target` with a full cone angle `fovDeg`. radius > 0 makes it a
  // disk area light of that radius centred at position, facing target.
  glm::vec3 position{0, 10, 0};
  glm::vec3 target{0, 0, 0};
  float fovDeg = 60.0f;
  float radius = 0.0f;
  // Directional: `direction` is the direction the light travels (unit length). angularRadiusDeg > 0 makes
  // it a sun disk of that angular radius.
  glm::vec3 direction{0, -1, 0};
  float angularRadiusDeg = 0.0f;

  bool isArea() const { return type == LightType::Spot ? radius > 0 : angularRadiusDeg > 0; }
  glm::vec3 axis() const;  // unit direction light travels along its centre axis
  std::string describe() const;  // the command-line form, for EXR provenance
};

// "spot:PX,PY,PZ:TX,TY,TZ:FOV_DEG[:RADIUS]" or "dir:DX,DY,DZ[:ANGULAR_RADIUS_DEG]". Throws
// std::invalid_argument naming the bad part: non-finite numbers, zero direction, P == T, fov outside
// (0, 180), negative radius, angular radius outside [0, 45).
Light parseLight(std::string_view spec);

}  // namespace penumbra
