// One glTF mesh primitive in its local space as an indexed triangle list: attributes read and checked,
// indices range-checked, strips and fans converted, flat normals made when NORMAL is absent, and its material with
// the texture coordinates an alpha-tested one reads.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "host/scene/gltf_accessor.h"
#include "host/scene/gltf_materials.h"

namespace penumbra::detail {

struct LocalPrimitive {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;  // one per position; may hold zero or non-finite ones (repaired later)
  std::vector<glm::uvec3> triangles;
  std::vector<glm::vec2> uvs;  // one per position when its material needs them (Material::needsUvs), else empty
  uint32_t material = 0;       // index into GltfMaterials::materials (the default material when it names none)
  bool isTriangles = true;     // false: points or lines, skipped (a warning was emitted)
  // Without NORMAL every triangle got three vertices of its own with its face normal (flat): source[i] is the
  // accessor vertex position i came from, so that morph targets and skins (gltf_deform.h) find their data and the
  // face normals are made again after them. Empty: position i is accessor vertex i.
  bool flat = false;
  std::vector<uint32_t> source;
};

// Throws SceneError for a missing POSITION, wrong accessor types, mismatched counts, non-finite positions or texture
// coordinates, indices out of range, a triangle list whose count is not a multiple of 3, an unknown mode, or an
// alpha-tested material's TEXCOORD_n that the primitive lacks.
LocalPrimitive readPrimitive(const GltfContext& ctx, int meshIndex, int primitiveIndex, const GltfMaterials& materials);

}  // namespace penumbra::detail
