// Convex geometry for LiSPSM's body B (Wimmer et al. 2004, sec. 4): solids as plane sets, the vertices of their
// intersection, the 2D hull of B seen along the light and its cut to a box. Private to host/views/lispsm.cpp.
#pragma once

#include <glm/glm.hpp>
#include <vector>

#include "host/scene/camera.h"
#include "host/scene/scene.h"

namespace penumbra::lispsm {

using Plane = glm::dvec4;  // f(p) = dot(xyz, p) + w >= 0 inside

// The camera frustum between view depths near and far, and the scene box, as world planes widened by `slack`
// world units (so corners on a face count as inside).
std::vector<Plane> frustumPlanes(const Camera& camera, double near, double far, double slack);
std::vector<Plane> boxPlanes(const Bounds& box, double slack);

// The clip volume |x_c|, |y_c|, |z_c| <= w_c of `clip` (world -> clip) as world planes (Gribb-Hartmann), widened
// by `slack` world units.
std::vector<Plane> clipPlanes(const glm::dmat4& clip, double slack);

// Vertices of (camera frustum slice) ∩ (scene box): every vertex of the intersection of two convex solids lies on
// an edge of one of them inside the other, so these points span the same convex hull.
std::vector<glm::dvec3> frustumBoxPoints(const Camera& camera, double near, double far, const Bounds& box,
                                         double slack);

// Vertices of the intersection of the half-spaces (every triple of planes meeting in a point inside all of them):
// any number of convex solids at once. Empty when the intersection is empty or has no vertex.
std::vector<glm::dvec3> intersectionPoints(const std::vector<Plane>& planes);

// Counter-clockwise convex hull (Andrew's monotone chain).
std::vector<glm::dvec2> convexHull(std::vector<glm::dvec2> points);

// The convex polygon cut to coordinate `axis` >= bound (sign 1) or <= bound (sign -1): one Sutherland-Hodgman pass.
std::vector<glm::dvec2> cutPolygon(const std::vector<glm::dvec2>& poly, int axis, double bound, double sign);

}  // namespace penumbra::lispsm
