// The scene's solids: connected groups of triangles (vertices welded by position) that close a volume, every edge
// shared by exactly two triangles that run it in opposite directions, none of which may discard fragments. A segment
// from a point outside a solid that meets it first crosses one of its triangles from that triangle's outer side, so a
// triangle whose outer side faces away from every point of a light (the whole light behind its plane) hides nothing
// from that light that the solid's other triangles do not: izb's area-light casters leave such triangles out.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "host/scene/scene.h"

namespace penumbra {

struct Solids {
  static constexpr int32_t kNone = -1;
  std::vector<int32_t> solidOf;       // per triangle: the solid it bounds, kNone when it bounds none
  std::vector<glm::vec4> outerPlane;  // per triangle bounding a solid: unit normal towards its outside, and n . p
  std::vector<Bounds> bounds;         // per solid
  std::vector<uint8_t> counterClockwiseOut;  // per solid: 1 when its triangles' counter-clockwise sides face out
  size_t triangles = 0;                      // triangles bounding a solid
};

// The solids of `scene`. A group is left out (kNone) when an edge is open, shared by more than two triangles or run
// the same way twice, when a triangle has two vertices at one position or its material may discard fragments, or
// when its signed volume is too small to tell its outside (a closed sheet of two faces back to back). A scene with an
// index out of range has none (the rasterizer's upload refuses it with the index named).
Solids findSolids(const Scene& scene);

// The light's extent for the test below: every point of a spot disk or sphere light lies within `radius` of `centre`;
// a sun's directions towards it lie within `angularRadius` (radians) of `towardSun`.
struct LightExtent {
  bool sun = false;
  glm::vec3 centre{0.0f}, towardSun{0.0f, 1.0f, 0.0f};
  float radius = 0.0f, angularRadius = 0.0f;
  bool operator==(const LightExtent&) const = default;
};
LightExtent lightExtent(const Light& light);

// Whether triangle t can be left out of the casters of `light`: it bounds a solid whose box the light's ball does not
// reach (the light lies outside the solid), and the whole light lies behind its outer plane, with a margin against
// the plane's rounding.
bool facesAwayFromLight(const Solids& solids, size_t t, const LightExtent& light);

}  // namespace penumbra
