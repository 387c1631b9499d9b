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

// The warning for a frame none of whose `alpha` values (the image's A channel) is 1: the camera sees no surface.
// Empty when some pixel is covered.
std::optional<std::string> emptyFrameWarning(const Scene& scene, const Camera& camera, std::span<const float> alpha);
// The same for a frame known to see a surface or not.
std::optional<std::string> emptyFrameWarning(const Scene& scene, const Camera& camera, bool seesSurface);

}  // namespace penumbra
