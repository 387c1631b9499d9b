// The flattened scene: its bounds, appending one scene to another (renumbering vertices and object ids)
// and transforming its geometry.
#include "host/scene/scene.h"

#include <stdexcept>

#include "host/scene/geometry.h"

namespace penumbra {

Bounds Scene::bounds() const {
  Bounds b;
  for (const glm::vec3& p : positions) b.grow(p);
  return b;
}

void Scene::append(const Scene& other) {
  const size_t vertexBase = positions.size(), objectBase = objectNames.size();
  if (vertexBase + other.positions.size() > std::numeric_limits<uint32_t>::max())
    throw std::length_error("Scene::append: more than 2^32 - 1 vertices");
  positions.insert(positions.end(), other.positions.begin(), other.positions.end());
  normals.insert(normals.end(), other.normals.begin(), other.normals.end());
  triangles.reserve(triangles.size() + other.triangles.size());
  for (const glm::uvec3& t : other.triangles) triangles.push_back(t + glm::uvec3(static_cast<uint32_t>(vertexBase)));
  objectIds.reserve(objectIds.size() + other.objectIds.size());
  for (uint32_t id : other.objectIds) objectIds.push_back(id + static_cast<uint32_t>(objectBase));
  objectNames.insert(objectNames.end(), other.objectNames.begin(), other.objectNames.end());
  cameras.insert(cameras.end(), other.cameras.begin(), other.cameras.end());
  lights.insert(lights.end(), other.lights.begin(), other.lights.end());
}

void transformGeometry(Scene& scene, const glm::mat4& transform) {
  detail::transformRange(scene, glm::dmat4(transform), 0, 0);
}

}  // namespace penumbra
