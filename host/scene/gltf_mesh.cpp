// Mesh primitive reading (glTF 2.0 spec 3.7.2.1 "Primitive topologies"): triangle strips become
// p_i = (v_i, v_{i+1+i%2}, v_{i+2-i%2}) and fans p_i = (v_{i+1}, v_{i+2}, v_0), which keeps the
// counter-clockwise front faces of the source.
#include "host/scene/gltf_mesh.h"

#include <cmath>
#include <numeric>

#include <fmt/format.h>

#include "host/scene/geometry.h"
#include "host/scene/limits.h"

namespace penumbra::detail {
namespace {

const char* modeName(int mode) {
  static constexpr const char* kNames[] = {"POINTS", "LINES", "LINE_LOOP", "LINE_STRIP"};
  return mode >= 0 && mode < 4 ? kNames[mode] : "?";
}

std::vector<glm::uvec3> assemble(const GltfContext& ctx, const std::string& what, int mode,
                                 const std::vector<uint32_t>& v) {
  std::vector<glm::uvec3> tris;
  const size_t n = v.size();
  if (mode == TINYGLTF_MODE_TRIANGLES) {
    if (n % 3 != 0) failGltf(ctx, fmt::format("{}: triangle list of {} vertices is not a multiple of 3", what, n));
    tris.reserve(n / 3);
    for (size_t i = 0; i + 2 < n; i += 3) tris.emplace_back(v[i], v[i + 1], v[i + 2]);
  } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
    for (size_t i = 0; i + 2 < n; ++i) tris.emplace_back(v[i], v[i + 1 + i % 2], v[i + 2 - i % 2]);
  } else {  // TINYGLTF_MODE_TRIANGLE_FAN
    for (size_t i = 0; i + 2 < n; ++i) tris.emplace_back(v[i + 1], v[i + 2], v[0]);
  }
  return tris;
}

uint64_t triangleCount(int mode, uint64_t n) { return mode == TINYGLTF_MODE_TRIANGLES ? n / 3 : (n >= 2 ? n - 2 : 0); }

void checkIndices(const GltfContext& ctx, int accessor, const std::vector<uint32_t>& indices, size_t vertexCount) {
  for (uint32_t i : indices)
    if (i >= vertexCount)
      failGltf(ctx, fmt::format("accessor {}: index {} out of range (vertex count {})", accessor, i, vertexCount));
}

void checkPositions(const GltfContext& ctx, int accessor, const std::vector<glm::vec3>& positions) {
  for (size_t i = 0; i < positions.size(); ++i) {
    const glm::vec3 p = positions[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      failGltf(ctx, fmt::format("accessor {}: POSITION {} is not finite ({}, {}, {})", accessor, i, p.x, p.y, p.z));
    if (!inCoordinateRange(p.x, p.y, p.z))
      failGltf(ctx, fmt::format("accessor {}: POSITION {} ({}, {}, {}) is outside +-{:g} (the renderer's coordinate "
                                "range)",
                                accessor, i, p.x, p.y, p.z, kMaxCoordinate));
  }
}

// No NORMAL: the spec asks for flat normals, so every triangle gets its own three vertices (texture coordinates
// follow them).
void makeFlat(LocalPrimitive& p) {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec2> uvs;
  positions.reserve(p.triangles.size() * 3);
  uvs.reserve(p.uvs.empty() ? 0 : p.triangles.size() * 3);
  p.normals.clear();
  p.normals.reserve(p.triangles.size() * 3);
  p.source.reserve(p.triangles.size() * 3);
  for (glm::uvec3& t : p.triangles) {
    const glm::vec3 n = faceNormal(p.positions[t.x], p.positions[t.y], p.positions[t.z]);
    const auto base = static_cast<uint32_t>(positions.size());
    for (int k = 0; k < 3; ++k) {
      positions.push_back(p.positions[t[k]]), p.normals.push_back(n), p.source.push_back(t[k]);
      if (!p.uvs.empty()) uvs.push_back(p.uvs[t[k]]);
    }
    t = glm::uvec3(base, base + 1, base + 2);
  }
  p.positions = std::move(positions);
  p.uvs = std::move(uvs);
  p.flat = true;
}

// The texture coordinates an alpha-tested material reads (TEXCOORD_<texCoord>), checked against the positions.
std::vector<glm::vec2> readUvs(const GltfContext& ctx, const tinygltf::Primitive& prim, const std::string& what,
                               const GltfMaterials& materials, uint32_t material, size_t vertexCount) {
  const Material& m = materials.materials[material];
  const std::string semantic = fmt::format("TEXCOORD_{}", m.texCoord);
  const auto it = prim.attributes.find(semantic);
  if (it == prim.attributes.end())
    failGltf(ctx, fmt::format("{}: material {} (\"{}\", alphaMode {}) reads {}, which the primitive does not have",
                              what, material, m.name, alphaModeName(m.alphaMode), semantic));
  std::vector<glm::vec2> uvs = readVec2(ctx, it->second, semantic);
  if (uvs.size() != vertexCount)
    failGltf(ctx, fmt::format("{}: {} has {} elements but POSITION has {}", what, semantic, uvs.size(), vertexCount));
  for (size_t i = 0; i < uvs.size(); ++i)
    if (!std::isfinite(uvs[i].x) || !std::isfinite(uvs[i].y))
      failGltf(ctx,
               fmt::format("accessor {}: {} {} is not finite ({}, {})", it->second, semantic, i, uvs[i].x, uvs[i].y));
  return uvs;
}

}  // namespace

LocalPrimitive readPrimitive(const GltfContext& ctx, int meshIndex, int primitiveIndex,
                             const GltfMaterials& materials) {
  const tinygltf::Primitive& prim =
      ctx.model.meshes[static_cast<size_t>(meshIndex)].primitives[static_cast<size_t>(primitiveIndex)];
  const std::string what = fmt::format("mesh {} primitive {}", meshIndex, primitiveIndex);
  LocalPrimitive out;
  if (prim.mode >= TINYGLTF_MODE_POINTS && prim.mode <= TINYGLTF_MODE_LINE_STRIP) {
    emitWarning(ctx.options, fmt::format("{}: {}: mode {} skipped (only triangles cast shadows)", ctx.file, what,
                                         modeName(prim.mode)));
    out.isTriangles = false;
    return out;
  }
  if (prim.mode < TINYGLTF_MODE_TRIANGLES || prim.mode > TINYGLTF_MODE_TRIANGLE_FAN)
    failGltf(ctx, fmt::format("{}: unknown mode {}", what, prim.mode));
  const auto position = prim.attributes.find("POSITION");
  if (position == prim.attributes.end()) failGltf(ctx, what + ": missing required attribute POSITION");
  out.positions = readVec3(ctx, position->second, "POSITION");
  checkPositions(ctx, position->second, out.positions);
  const uint64_t elements = prim.indices >= 0 ? accessorAt(ctx, prim.indices).count : out.positions.size();
  if (triangleCount(prim.mode, elements) > ctx.options.maxTriangles)
    failGltf(ctx, fmt::format("{}: {} triangles exceed the limit of {}", what, triangleCount(prim.mode, elements),
                              ctx.options.maxTriangles));
  std::vector<uint32_t> indices;
  if (prim.indices >= 0) {
    indices = readIndices(ctx, prim.indices);
    checkIndices(ctx, prim.indices, indices, out.positions.size());
  } else {
    indices.resize(out.positions.size());
    std::iota(indices.begin(), indices.end(), 0u);
  }
  out.triangles = assemble(ctx, what, prim.mode, indices);
  out.material = prim.material >= 0 ? static_cast<uint32_t>(prim.material) : materials.defaultMaterial;
  if (materials.materials[out.material].needsUvs())
    out.uvs = readUvs(ctx, prim, what, materials, out.material, out.positions.size());
  const auto normal = prim.attributes.find("NORMAL");
  if (normal == prim.attributes.end()) {
    makeFlat(out);
    return out;
  }
  out.normals = readVec3(ctx, normal->second, "NORMAL");
  if (out.normals.size() != out.positions.size())
    failGltf(ctx, fmt::format("{}: NORMAL has {} elements but POSITION has {}", what, out.normals.size(),
                              out.positions.size()));
  return out;
}

}  // namespace penumbra::detail
