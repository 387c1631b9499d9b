// The flattened scene: its bounds, appending one scene to another (renumbering vertices, object and material ids and
// alpha textures), its materials' summary and transforming its geometry.
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

float Scene::boundingRadius() const { return triangles.empty() ? 0.0f : bounds().radius(); }

namespace {

// Gives a scene without materials one plain material for all its triangles, so it can join a scene that has some.
Scene withMaterials(const Scene& s) {
  Scene out;
  out.materials = {plainMaterial()};
  out.materialIds.assign(s.triangles.size(), 0);
  return out;
}

void appendUvs(Scene& scene, const Scene& other, size_t vertexBase) {
  if (scene.uvs.empty() && other.uvs.empty()) return;
  scene.uvs.resize(vertexBase, glm::vec2(0.0f));  // a part without texture coordinates: zeros, never read
  if (other.uvs.empty())
    scene.uvs.resize(vertexBase + other.positions.size(), glm::vec2(0.0f));
  else
    scene.uvs.insert(scene.uvs.end(), other.uvs.begin(), other.uvs.end());
}

void appendMaterials(Scene& scene, const Scene& other) {
  if (other.materials.empty() && (scene.materials.empty() || other.triangles.empty())) return;
  if (scene.materials.empty() && !scene.triangles.empty()) {
    Scene plain = withMaterials(scene);
    scene.materials = std::move(plain.materials), scene.materialIds = std::move(plain.materialIds);
  }
  const Scene plain = other.materials.empty() ? withMaterials(other) : Scene{};
  const Scene& source = other.materials.empty() ? plain : other;
  const auto materialBase = static_cast<uint32_t>(scene.materials.size());
  const auto textureBase = static_cast<int>(scene.alphaTextures.size());
  for (Material m : source.materials) {
    if (m.alphaTexture >= 0) m.alphaTexture += textureBase;
    scene.materials.push_back(std::move(m));
  }
  for (uint32_t id : source.materialIds) scene.materialIds.push_back(id + materialBase);
  for (AlphaTexture t : other.alphaTextures) {
    t.offset += scene.alphaTexels.size();
    scene.alphaTextures.push_back(std::move(t));
  }
  scene.alphaTexels.insert(scene.alphaTexels.end(), other.alphaTexels.begin(), other.alphaTexels.end());
}

}  // namespace

bool Scene::anyMayDiscard() const {
  return std::any_of(materials.begin(), materials.end(), [](const Material& m) { return m.mayDiscard(); });
}

void Scene::append(const Scene& other) {
  const size_t vertexBase = positions.size(), objectBase = objectNames.size();
  if (vertexBase + other.positions.size() > std::numeric_limits<uint32_t>::max())
    throw std::length_error("Scene::append: more than 2^32 - 1 vertices");
  appendUvs(*this, other, vertexBase);
  appendMaterials(*this, other);
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

std::string describeMaterials(const Scene& scene) {
  if (scene.materials.empty()) return {};
  std::vector<bool> used(scene.materials.size(), false);
  for (uint32_t id : scene.materialIds) used[id] = true;
  size_t count = 0, mask = 0, blend = 0, single = 0;
  for (size_t i = 0; i < scene.materials.size(); ++i) {
    if (!used[i]) continue;
    const Material& m = scene.materials[i];
    ++count, mask += m.alphaMode == AlphaMode::kMask, blend += m.alphaMode == AlphaMode::kBlend;
    single += !m.doubleSided;
  }
  const double bytes = static_cast<double>(scene.alphaTexels.size());
  const std::string size =
      bytes < (1 << 20) ? fmt::format("{:.1f} KiB", bytes / (1 << 10)) : fmt::format("{:.1f} MiB", bytes / (1 << 20));
  return fmt::format(
      "{} material{} ({} MASK, {} BLEND as MASK, {} single-sided), {} alpha texture{}, {} of alpha texels", count,
      count == 1 ? "" : "s", mask, blend, single, scene.alphaTextures.size(),
      scene.alphaTextures.size() == 1 ? "" : "s", size);
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
