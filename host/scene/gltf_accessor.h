// Reading glTF accessors into plain arrays with every range checked first: accessor -> bufferView ->
// buffer bounds, stride and count overflow, component types, and sparse substitution.
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <tiny_gltf.h>

#include "host/scene/load_options.h"

namespace penumbra::detail {

struct GltfContext {
  const tinygltf::Model& model;
  const std::string& file;  // for messages: "FILE: accessor 3: ..."
  const LoadOptions& options;
  // No accessor may hold more elements than this (bounds the memory an accessor without bufferView asks for).
  uint64_t maxElements() const { return std::max(options.maxVertices, 3 * options.maxTriangles + 2); }
};

[[noreturn]] void failGltf(const GltfContext& ctx, const std::string& message);

// The accessor, or SceneError "FILE: accessor N does not exist".
const tinygltf::Accessor& accessorAt(const GltfContext& ctx, int index);

// A VEC3 FLOAT accessor (POSITION, NORMAL); `semantic` names it in messages. Non-finite values are kept.
std::vector<glm::vec3> readVec3(const GltfContext& ctx, int index, const char* semantic);

// A VEC2 accessor of FLOAT, or of normalized UNSIGNED_BYTE / UNSIGNED_SHORT (TEXCOORD_n, glTF 2.0 sec. 3.7.2.1),
// as floats in [0, 1] for the normalized ones; `semantic` names it in messages. Non-finite values are kept.
std::vector<glm::vec2> readVec2(const GltfContext& ctx, int index, const std::string& semantic);

// A SCALAR UNSIGNED_BYTE / UNSIGNED_SHORT / UNSIGNED_INT accessor, widened to 32 bits.
std::vector<uint32_t> readIndices(const GltfContext& ctx, int index);

// An accessor of `components` numbers per element (1 SCALAR, 2 VEC2, 3 VEC3, 4 VEC4, 16 MAT4) as floats, element
// after element: FLOAT, or with `normalizedToo` also the normalized integer types, decoded as glTF 2.0 sec. 3.11
// prescribes (unsigned c / max, signed max(c / max, -1)). `semantic` names it in messages. Non-finite values kept.
std::vector<float> readFloats(const GltfContext& ctx, int index, int components, bool normalizedToo,
                              const char* semantic);

// A VEC4 UNSIGNED_BYTE / UNSIGNED_SHORT accessor that is not normalized (JOINTS_n).
std::vector<glm::uvec4> readJoints(const GltfContext& ctx, int index, const char* semantic);

}  // namespace penumbra::detail
