// Geometry helpers shared by the loaders: transforming a range of a scene's vertices and triangles
// (normals by the cofactor matrix, winding flipped for mirrors) and repairing unusable normals.
#pragma once

#include <cstddef>

#include <glm/glm.hpp>

#include "host/scene/scene.h"

namespace penumbra::detail {

// sign(det m) * cofactor(m): the inverse-transpose up to a positive factor, so it keeps normals pointing
// the right way, and it stays defined when m is singular (scale 0).
glm::dmat3 normalMatrix(const glm::dmat3& m);

// Transforms vertices [firstVertex, end) and, when det(m) < 0, reverses triangles [firstTriangle, end)
// so that front faces stay counter-clockwise. Normals that come out unusable are left as they are.
void transformRange(Scene& scene, const glm::dmat4& m, size_t firstVertex, size_t firstTriangle);

// Normalises normals of vertices [firstVertex, end); a zero or non-finite one is replaced by the
// area-weighted normal of the triangles [firstTriangle, end) that use it, or +Y if it has none.
// Returns how many were replaced.
size_t repairNormals(Scene& scene, size_t firstVertex, size_t firstTriangle);

// Unit normal of the counter-clockwise triangle (a, b, c), or zero for a degenerate one.
glm::vec3 faceNormal(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c);

}  // namespace penumbra::detail
