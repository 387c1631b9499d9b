// Conversions between the C API's plain structs (pn_camera, pn_light) and the internal Camera and Light.
#pragma once

#include "host/scene/camera.h"
#include "host/scene/light.h"
#include "penumbra/scene.h"

namespace penumbra::api {

// The caller's structs carry their size (pn_camera_init, pn_light_init): reading one requires it to hold the first
// version's fields, and filling one keeps it and writes only what it holds. `function` and `name` name the argument
// in the std::invalid_argument thrown for a struct the init function did not prepare.
pn_camera toC(const Camera& camera);  // size: sizeof(pn_camera)
void fill(const Camera& camera, pn_camera* out, const char* function, const char* name);
// Also throws for an image size outside 1..kMaxImageSide.
Camera fromC(const pn_camera& camera, const char* function, const char* name);
pn_light toC(const Light& light);  // size: sizeof(pn_light); the name points into `light`
void fill(const Light& light, pn_light* out, const char* function, const char* name);  // the name points into `light`
Light fromC(const pn_light& light, const char* function, const char* name);  // also throws for an unknown type

}  // namespace penumbra::api
