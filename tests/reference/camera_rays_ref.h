// Double-precision reference of what a camera sees: one primary ray per pixel centre, built from the camera's eye,
// target, up and fov (or orthographic half height) alone, never from its matrices, against every triangle.
#pragma once

#include <cstdint>
#include <vector>

#include "host/scene/scene.h"

namespace penumbra::ref {

inline constexpr int64_t kNoHit = -1;

// The nearest triangle hit through each pixel centre (row 0 at the bottom, like the G-buffer), kNoHit for none.
// Perspective rays start at the eye; orthographic rays are parallel to the view direction and start on the plane
// through the eye. Hits behind the ray's start, or outside the camera's clipNear..clipFar, do not count.
std::vector<int64_t> primaryHits(const Scene& scene, const Camera& camera);

}  // namespace penumbra::ref
