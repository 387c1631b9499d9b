// Default views for scenes that bring none (a bare .gltf/.glb): a camera that sees the whole bounds and a
// soft spot light above and to the side whose cone covers them and the ground around them.
#pragma once

#include "host/scene/camera.h"
#include "host/scene/light.h"
#include "host/scene/scene.h"

namespace penumbra {

// Looks at bounds.center() from above-front-right, far enough that the bounding sphere fits the frustum.
Camera framingCamera(const Bounds& bounds, int width = 1280, int height = 720, float fovYDeg = 45.0f);

// A disk spot light (radius 5% of the bounding radius) above and to the side, aimed at the bottom centre,
// with a cone that holds the bounding sphere grown by the ground margin.
Light framingLight(const Bounds& bounds);

}  // namespace penumbra
