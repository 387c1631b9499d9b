// Procedural building blocks. Boxes are six quads over the corners c(i) = (i&1 ? max.x : min.x,
// i&2 ? max.y : min.y, i&4 ? max.z : min.z), each face listed counter-clockwise from outside.
#include "host/scene/procedural_mesh.h"

#include <algorithm>

#include "host/scene/geometry.h"

namespace penumbra::detail {

namespace {

// Material ids for `triangles` new triangles and zero texture coordinates for `vertices` new vertices, where the
// scene keeps them.
void extendAttributes(Scene& scene, size_t vertices, size_t triangles) {
  if (!scene.uvs.empty()) scene.uvs.resize(scene.uvs.size() + vertices, glm::vec2(0.0f));
  if (scene.materials.empty()) return;
  const auto plain = std::find_if(scene.materials.begin(), scene.materials.end(),
                                  [](const Material& m) { return m.name == plainMaterial().name; });
  const auto id = static_cast<uint32_t>(plain - scene.materials.begin());
  if (plain == scene.materials.end()) scene.materials.push_back(plainMaterial());
  scene.materialIds.insert(scene.materialIds.end(), triangles, id);
}

}  // namespace

uint32_t addObject(Scene& scene, std::string name) {
  scene.objectNames.push_back(std::move(name));
  return static_cast<uint32_t>(scene.objectNames.size() - 1);
}

void addTriangle(Scene& scene, uint32_t object, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
  const auto base = static_cast<uint32_t>(scene.positions.size());
  const glm::vec3 n = faceNormal(a, b, c);
  extendAttributes(scene, 3, 1);
  scene.positions.insert(scene.positions.end(), {a, b, c});
  scene.normals.insert(scene.normals.end(), 3, n);
  scene.triangles.emplace_back(base, base + 1, base + 2);
  scene.objectIds.push_back(object);
}

namespace {

void addQuadGeometry(Scene& scene, uint32_t object, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c,
                     const glm::vec3& d) {
  const auto base = static_cast<uint32_t>(scene.positions.size());
  const glm::vec3 n = faceNormal(a, b, c);
  scene.positions.insert(scene.positions.end(), {a, b, c, d});
  scene.normals.insert(scene.normals.end(), 4, n);
  scene.triangles.emplace_back(base, base + 1, base + 2);
  scene.triangles.emplace_back(base, base + 2, base + 3);
  scene.objectIds.insert(scene.objectIds.end(), 2, object);
}

}  // namespace

void addQuad(Scene& scene, uint32_t object, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c,
             const glm::vec3& d) {
  extendAttributes(scene, 4, 2);
  addQuadGeometry(scene, object, a, b, c, d);
}

void addTexturedQuad(Scene& scene, uint32_t object, uint32_t material, const glm::vec3& a, const glm::vec3& b,
                     const glm::vec3& c, const glm::vec3& d) {
  scene.uvs.resize(scene.positions.size(), glm::vec2(0.0f));  // the first texture coordinates of the scene
  scene.uvs.insert(scene.uvs.end(), {glm::vec2(0, 0), glm::vec2(0, 1), glm::vec2(1, 1), glm::vec2(1, 0)});
  scene.materialIds.insert(scene.materialIds.end(), 2, material);
  addQuadGeometry(scene, object, a, b, c, d);
}

void addBox(Scene& scene, uint32_t object, const glm::vec3& min, const glm::vec3& max) {
  const auto c = [&](int i) { return glm::vec3(i & 1 ? max.x : min.x, i & 2 ? max.y : min.y, i & 4 ? max.z : min.z); };
  static constexpr int kFaces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5},   // -X, +X
                                       {0, 1, 5, 4}, {2, 6, 7, 3},   // -Y, +Y
                                       {0, 2, 3, 1}, {4, 5, 7, 6}};  // -Z, +Z
  for (const auto& f : kFaces) addQuad(scene, object, c(f[0]), c(f[1]), c(f[2]), c(f[3]));
}

void addHorizontalQuad(Scene& scene, uint32_t object, float x0, float x1, float z0, float z1, float y) {
  addQuad(scene, object, {x0, y, z0}, {x0, y, z1}, {x1, y, z1}, {x1, y, z0});
}

void addGroundPlane(Scene& scene, const Bounds& models, float margin, float y) {
  const glm::vec3 size = models.max - models.min;
  float extent = std::max(size.x, size.z);
  if (!(extent > 0.0f)) extent = std::max(size.y, 1.0f);  // a vertical sliver or a point: still a usable ground
  const float reach = margin * extent;
  addHorizontalQuad(scene, addObject(scene, "ground"), models.min.x - reach, models.max.x + reach, models.min.z - reach,
                    models.max.z + reach, y);
}

}  // namespace penumbra::detail
