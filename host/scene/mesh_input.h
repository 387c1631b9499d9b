// A scene from a caller's own triangle arrays (the public API's pn_scene_create): each mesh its positions, optional
// normals, 32-bit indices, an optional transform, a name and its sidedness, checked as the glTF loader checks a
// primitive (finite positions, indices in range, the loader's size limits).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "host/scene/load_options.h"
#include "host/scene/scene.h"

namespace penumbra {

struct MeshInput {
  std::span<const float> positions;    // x, y, z per vertex
  std::span<const float> normals;      // x, y, z per vertex, or empty: area-weighted normals of the triangles
  std::span<const uint32_t> indices;   // three per triangle, counter-clockwise front faces
  std::optional<glm::mat4> transform;  // to world space (column-major, as GLM and glTF); none: identity
  std::string name;                    // "": "mesh N"
  bool doubleSided = true;             // false: back faces culled in the camera's view (glTF doubleSided false)
};

// The meshes' triangles in world space, one object per mesh, with `lights` (named as a scene file's are). Throws
// SceneError naming the mesh and the element: "mesh 1 \"rock\": triangle 7 index 2 is 120, out of range (vertex
// count 100)", a component count that is not a multiple of 3, a position or transform that is not finite, more
// triangles or vertices than `limits` allow.
Scene meshScene(std::span<const MeshInput> meshes, std::vector<Light> lights, const LoadOptions& limits = {});

}  // namespace penumbra
