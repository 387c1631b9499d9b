// Checks of a frame's inputs before any work and of its result after: every coordinate within the renderer's range
// (host/scene/limits.h), named by what it belongs to; a frame that sees no surface is named with its likely cause.
#pragma once

#include <optional>
#include <span>
#include <string>

#include "host/scene/camera.h"
#include "host/scene/light.h"
#include "host/scene/scene.h"

namespace penumbra {

// Throws std::invalid_argument naming the camera, the light or the scene's bounds when a coordinate lies outside
// +-kMaxCoordinate: what a Scene built by hand or a Camera set in code can hold, where the loaders refuse it first.
void checkFrameRange(const Scene& scene, const Camera& camera, std::span<const Light> lights);

// The warning for an area light (a spot's disk, a point's sphere) that the scene's geometry comes within its radius
// of: a surface inside the light (or touching its disk) has no defined visibility, and the shadow maps and the ray
// tracer answer differently there (`point:0,5,0:1e17` over builtin:box: 0.49 MAE between `render` and `reference`,
// with no word said). Names the light, its radius and the nearest distance. Empty otherwise (and for suns, whose
// radius is an angle). O(triangles) only when the radius reaches the scene's bounds; stops at the first triangle in
// reach.
std::optional<std::string> lightReachWarning(const Scene& scene, const Light& light);

// The warning for a frame none of whose `alpha` values (the image's A channel) is 1: the camera sees no surface.
// Empty when some pixel is covered.
std::optional<std::string> emptyFrameWarning(const Scene& scene, const Camera& camera, std::span<const float> alpha);
// The same for a frame known to see a surface or not.
std::optional<std::string> emptyFrameWarning(const Scene& scene, const Camera& camera, bool seesSurface);

}  // namespace penumbra
