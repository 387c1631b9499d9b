#include "host/scene/mesh_input.h"

#include <fmt/format.h>

#include <cmath>

#include "host/scene/geometry.h"
#include "host/scene/light_names.h"
#include "host/scene/procedural_mesh.h"

namespace penumbra {
namespace {

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

void checkCounts(const MeshInput& mesh, const std::string& what) {
  if (mesh.positions.size() % 3 != 0)
    throw SceneError(fmt::format("{}: {} position floats are not 3 per vertex", what, mesh.positions.size()));
  if (!mesh.normals.empty() && mesh.normals.size() != mesh.positions.size())
    throw SceneError(fmt::format("{}: {} normal floats for {} vertices (3 per vertex, or none)", what,
                                 mesh.normals.size(), mesh.positions.size() / 3));
  if (mesh.indices.size() % 3 != 0)
    throw SceneError(fmt::format("{}: {} indices are not 3 per triangle", what, mesh.indices.size()));
  if (mesh.transform) {
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r)
        if (!std::isfinite((*mesh.transform)[c][r]))
          throw SceneError(fmt::format("{}: transform element [{}][{}] (column, row) is not finite", what, c, r));
  }
}

// One mesh as a scene part in world space: its vertices, triangles and object; a single-sided mesh gets a
// single-sided opaque material.
Scene meshPart(const MeshInput& mesh, const std::string& what, const std::string& name) {
  Scene part;
  const size_t vertices = mesh.positions.size() / 3;
  for (size_t v = 0; v < vertices; ++v) {
    const glm::vec3 p(mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]);
    if (!finite(p)) throw SceneError(fmt::format("{}: position {} is not finite ({}, {}, {})", what, v, p.x, p.y, p.z));
    part.positions.push_back(p);
    part.normals.push_back(mesh.normals.empty()
                               ? glm::vec3(0.0f)
                               : glm::vec3(mesh.normals[3 * v], mesh.normals[3 * v + 1], mesh.normals[3 * v + 2]));
  }
  const uint32_t object = detail::addObject(part, name);
  for (size_t t = 0; t < mesh.indices.size() / 3; ++t) {
    for (int k = 0; k < 3; ++k)
      if (mesh.indices[3 * t + k] >= vertices)
        throw SceneError(fmt::format("{}: triangle {} index {} is {}, out of range (vertex count {})", what, t, k,
                                     mesh.indices[3 * t + k], vertices));
    part.triangles.emplace_back(mesh.indices[3 * t], mesh.indices[3 * t + 1], mesh.indices[3 * t + 2]);
    part.objectIds.push_back(object);
  }
  if (mesh.transform) detail::transformRange(part, glm::dmat4(*mesh.transform), 0, 0);
  for (size_t v = 0; v < vertices; ++v)
    if (!finite(part.positions[v]))
      throw SceneError(fmt::format("{}: position {} is not finite after the transform", what, v));
  detail::repairNormals(part, 0, 0);  // none given, zero or not finite: area-weighted
  if (!mesh.doubleSided) {
    Material single = plainMaterial();
    single.name = "(single-sided)";
    single.doubleSided = false;
    part.materials = {single};
    part.materialIds.assign(part.triangles.size(), 0);
  }
  return part;
}

}  // namespace

Scene meshScene(std::span<const MeshInput> meshes, std::vector<Light> lights, const LoadOptions& limits) {
  Scene scene;
  uint64_t triangles = 0, vertices = 0;
  for (size_t i = 0; i < meshes.size(); ++i) {
    const MeshInput& mesh = meshes[i];
    const std::string name = mesh.name.empty() ? fmt::format("mesh {}", i) : mesh.name;
    const std::string what = mesh.name.empty() ? name : fmt::format("mesh {} \"{}\"", i, mesh.name);
    checkCounts(mesh, what);
    triangles += mesh.indices.size() / 3, vertices += mesh.positions.size() / 3;
    if (triangles > limits.maxTriangles || vertices > limits.maxVertices)
      throw SceneError(
          fmt::format("{}: the meshes so far hold {} triangles and {} vertices, over the limits of {} "
                      "and {}",
                      what, triangles, vertices, limits.maxTriangles, limits.maxVertices));
    scene.append(meshPart(mesh, what, name));
  }
  nameLights(lights);
  scene.lights = std::move(lights);
  return scene;
}

}  // namespace penumbra
