// The parts of a JSON scene file that are read the same way wherever they appear: cameras, lights and
// model placements. Every field is checked; messages name the file and the JSON pointer.
#pragma once

#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "host/scene/camera.h"
#include "host/scene/json_util.h"
#include "host/scene/light.h"

namespace penumbra::detail {

// {"eye":[..], "target":[..], "fovy_deg": 45, "size": [1280, 720]}
Camera readCamera(const Json& value, const std::string& file, const std::string& pointer);

// {"type":"spot", "position":[..], "target":[..], "fov_deg":60, "radius":0.5},
// {"type":"dir", "direction":[..], "angular_radius_deg":0.5} or {"type":"point", "position":[..], "radius":0.5},
// each with an optional "name" and an optional "technique" with its "params" ({"technique": "pcss", "params":
// {"light-size": 2}}: Light::technique and Light::params).
Light readLight(const Json& value, const std::string& file, const std::string& pointer);

// {"name":"Lamp", "radius":0.2} (spot and point lights) or {"name":"Sun", "angular_radius_deg":0.27}
// (directional): sets the size of the light of `lights` with that name, or throws naming the lights there are.
void readLightSize(const Json& value, const std::string& file, const std::string& pointer, std::vector<Light>& lights);

// T * R * S from the optional "translation", "rotation_deg" (X, then Y, then Z, about the world axes:
// R = Rz * Ry * Rx) or "rotation_quat" ([x, y, z, w], glTF order), and "scale" (a number or [x, y, z]).
glm::mat4 readPlacement(ObjectReader& model);

}  // namespace penumbra::detail
