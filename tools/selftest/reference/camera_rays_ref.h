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
// through the eye. Hits behind the ray's start, or outside the camera's clipNear..clipFar, do not count; nor do, as
// in the camera's G-buffer, back faces of single-sided materials and alpha-tested hits whose alpha
// (tools/selftest/reference/alpha_ref.h) is below the cutoff. `alphaBorder` (optional): 1 per pixel where some
// alpha-tested hit lay within kAlphaBorder of its cutoff or crossed it within kUvSlack
// (tools/selftest/reference/raster_ref.h).
std::vector<int64_t> primaryHits(const Scene& scene, const Camera& camera, std::vector<uint8_t>* alphaBorder = nullptr);

}  // namespace penumbra::ref
