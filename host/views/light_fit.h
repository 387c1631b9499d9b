// What the light's frustum is fitted to: the light-space box of the receivers the camera sees (a min/max
// reduction of the G-buffer on the device) and, once the map is drawn, the depth range of its casters
// (kernels/fit.cl). host/views/views.h turns these into the light's view.
#pragma once

#include <glm/glm.hpp>

#include "host/cl/buffer.h"
#include "host/cl/context.h"
#include "host/scene/light.h"
#include "host/scene/scene.h"
#include "raster/rasterizer.h"

namespace penumbra {

// Light-eye box of the visible receivers. Spot lights: x, y are the tangents x/d, y/d (the unit a perspective
// map's texels are uniform in); directional lights: light-eye x, y. depth is linear light depth d = -z_eye.
struct ReceiverBounds {
  bool empty = true;  // the camera sees no surface (in front of the light)
  glm::vec2 lo{0.0f}, hi{0.0f};
  float depthMin = 0.0f, depthMax = 0.0f;
};

// The light's world -> eye matrix before fitting (its orientation does not depend on the fit). Throws
// std::invalid_argument for a point light, which has one per cube face (host/views/cube.h cubeFaceLight).
glm::mat4 lightEyeMatrix(const Light& light, const Bounds& scene);

// Box of the covered G-buffer pixels seen from `lightEye`. Launch "fit/fit_receivers_partial".
ReceiverBounds reduceReceivers(Context& ctx, const GBuffer& gbuffer, const glm::mat4& lightEye, bool perspective);

// Finite min and max of `count` depths (+INFINITY background ignored); {+inf, -inf} when none is finite.
// Launch "fit/fit_depth_partial".
struct DepthRange {
  float min, max;
};
DepthRange reduceDepthRange(Context& ctx, const Buffer<float>& depth, size_t count);

}  // namespace penumbra
