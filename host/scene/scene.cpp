// The flattened scene: its bounds, appending one scene to another (renumbering vertices and object ids)
// and transforming its geometry.
#include "host/scene/scene.h"

#include <algorithm>
#include <stdexcept>

#include <fmt/format.h>

#include "host/scene/geometry.h"
#include "host/scene/spec_parse.h"

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
  const int gltfBase =
      static_cast<int>(std::count_if(cameras.begin(), cameras.end(), [](const Camera& c) { return c.gltfIndex >= 0; }));
  for (Camera c : other.cameras) {
    if (c.gltfIndex >= 0) c.gltfIndex += gltfBase;
    cameras.push_back(std::move(c));
  }
  lights.insert(lights.end(), other.lights.begin(), other.lights.end());
}

const Camera& findGltfCamera(const Scene& scene, std::string_view key) {
  long long index = -1;
  try {
    index = detail::parseInteger(key, "index");
  } catch (const std::invalid_argument&) {  // not a number: a name
  }
  std::string available;
  for (const Camera& c : scene.cameras) {
    if (c.gltfIndex < 0) continue;
    if (c.gltfIndex == index || (index < 0 && c.name == key)) return c;
    available += (available.empty() ? "" : ", ") + c.label().substr(5);  // without "gltf:"
  }
  throw std::invalid_argument(
      fmt::format("no glTF camera \"{}\" ({})", key,
                  available.empty() ? "the scene has no glTF cameras" : "the scene's glTF cameras: " + available));
}

void transformCameras(Scene& scene, const glm::mat4& transform) {
  for (Camera& c : scene.cameras) {
    c.eye = glm::vec3(transform * glm::vec4(c.eye, 1.0f));
    c.target = glm::vec3(transform * glm::vec4(c.target, 1.0f));
    c.up = glm::mat3(transform) * c.up;
  }
}

void transformGeometry(Scene& scene, const glm::mat4& transform) {
  detail::transformRange(scene, glm::dmat4(transform), 0, 0);
}

}  // namespace penumbra
