// Conversions between the C API's plain structs (pn_camera, pn_light) and the internal Camera and Light.
#pragma once

#include "host/scene/camera.h"
#include "host/scene/light.h"
#include "penumbra/scene.h"

namespace penumbra::api {

pn_camera toC(const Camera& camera);
Camera fromC(const pn_camera& camera);  // throws std::invalid_argument for a size outside 1..kMaxImageSide
pn_light toC(const Light& light);       // the name points into `light`
Light fromC(const pn_light& light);     // throws std::invalid_argument for an unknown type

}  // namespace penumbra::api
