// glTF loading pipeline: read (contained, capped) -> GLB container check -> JSON schema and required
// extensions -> tinygltf -> animations sampled at --time (gltf_animation.h) -> node forest -> materials (the alpha
// textures of the alpha-tested ones the instances use, gltf_materials.h) -> primitives read once per mesh (instances
// share them) -> limits checked -> every instance morphed and skinned where it must be (gltf_deform.h) and
// transformed into world space -> the default scene's cameras (gltf_camera.h) and KHR_lights_punctual lights
// (gltf_lights.h).
#include "host/scene/gltf_loader.h"

#include <cmath>
#include <map>
#include <set>
#include <utility>

#include <fmt/format.h>

#include "host/scene/geometry.h"
#include "host/scene/gltf_animation.h"
#include "host/scene/gltf_camera.h"
#include "host/scene/gltf_deform.h"
#include "host/scene/gltf_glb.h"
#include "host/scene/gltf_lights.h"
#include "host/scene/gltf_mesh.h"
#include "host/scene/gltf_nodes.h"
#include "host/scene/gltf_schema.h"
#include "host/scene/gltf_tinygltf.h"
#include "host/scene/limits.h"

namespace penumbra {
namespace detail {
namespace {

using PrimitiveKey = std::pair<int, int>;  // mesh, primitive
using PrimitiveCache = std::map<PrimitiveKey, LocalPrimitive>;

ParsedGltf parseFile(const std::vector<unsigned char>& bytes, const std::filesystem::path& path,
                     const std::string& display, const LoadOptions& options, FileReader& reader) {
  const bool binary = hasGlbMagic(bytes) || path.extension() == ".glb" || path.extension() == ".GLB";
  const GlbChunks glb = binary ? parseGlb(bytes, display) : GlbChunks{};
  const std::string_view json =
      binary ? glb.json : std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  if (glb.trailing > 0)
    emitWarning(options, fmt::format("{}: GLB: {} bytes after the container's {} (its header's length) are ignored",
                                     display, glb.trailing, glb.length));
  // tinygltf parses the text again into its own DOM and keeps a struct per element: bounded before either exists.
  const ParseBudget budget{options.maxParseBytes, 100, &tinygltfElementBytes, "LoadOptions::maxParseBytes"};
  checkGltfJson(parseJson(display, json, false, options.maxJsonValues, &budget), display);
  return parseWithTinygltf(bytes, binary ? glb.length : bytes.size(), binary, path.parent_path(), reader, display,
                           options);
}

// The materials the instanced meshes' primitives use (-1: some primitive has none).
std::set<int> usedMaterials(const GltfContext& ctx, const std::vector<NodeInstance>& instances) {
  std::set<int> used;
  for (const NodeInstance& inst : instances) {
    const int mesh = ctx.model.nodes[static_cast<size_t>(inst.node)].mesh;
    if (mesh < 0 || static_cast<size_t>(mesh) >= ctx.model.meshes.size()) continue;
    for (const auto& prim : ctx.model.meshes[static_cast<size_t>(mesh)].primitives) used.insert(prim.material);
  }
  return used;
}

// Reads each primitive of every instanced mesh once and checks the flattened totals against the limits.
PrimitiveCache readPrimitives(const GltfContext& ctx, const std::vector<NodeInstance>& instances,
                              const GltfMaterials& materials) {
  PrimitiveCache cache;
  uint64_t triangles = 0, vertices = 0;
  for (const NodeInstance& inst : instances) {
    const int mesh = ctx.model.nodes[static_cast<size_t>(inst.node)].mesh;
    if (mesh < 0) continue;
    if (static_cast<size_t>(mesh) >= ctx.model.meshes.size())
      failGltf(ctx, fmt::format("node {}: mesh {} does not exist", inst.node, mesh));
    for (size_t p = 0; p < ctx.model.meshes[static_cast<size_t>(mesh)].primitives.size(); ++p) {
      const PrimitiveKey key{mesh, static_cast<int>(p)};
      auto it = cache.find(key);
      if (it == cache.end()) it = cache.emplace(key, readPrimitive(ctx, mesh, static_cast<int>(p), materials)).first;
      triangles += it->second.triangles.size();
      vertices += it->second.positions.size();
      if (triangles > ctx.options.maxTriangles || vertices > ctx.options.maxVertices)
        failGltf(ctx, fmt::format("the scene flattens to more than {} triangles or {} vertices (the limits)",
                                  ctx.options.maxTriangles, ctx.options.maxVertices));
    }
  }
  return cache;
}

std::string objectName(const tinygltf::Model& model, int node, int mesh, int primitive) {
  const std::string& nodeName = model.nodes[static_cast<size_t>(node)].name;
  const std::string& meshName = model.meshes[static_cast<size_t>(mesh)].name;
  return fmt::format("{}/{}/{}", nodeName.empty() ? std::to_string(node) : nodeName,
                     meshName.empty() ? std::to_string(mesh) : meshName, primitive);
}

// `uvs`: whether the scene keeps texture coordinates (zeros for primitives that read none).
void appendInstance(Scene& scene, const LocalPrimitive& prim, const glm::dmat4& world, uint32_t objectId, bool uvs) {
  const size_t vbase = scene.positions.size(), tbase = scene.triangles.size();
  scene.positions.insert(scene.positions.end(), prim.positions.begin(), prim.positions.end());
  scene.normals.insert(scene.normals.end(), prim.normals.begin(), prim.normals.end());
  if (uvs && prim.uvs.empty()) scene.uvs.resize(scene.positions.size(), glm::vec2(0.0f));
  if (uvs && !prim.uvs.empty()) scene.uvs.insert(scene.uvs.end(), prim.uvs.begin(), prim.uvs.end());
  for (const glm::uvec3& t : prim.triangles) scene.triangles.push_back(t + glm::uvec3(static_cast<uint32_t>(vbase)));
  scene.objectIds.insert(scene.objectIds.end(), prim.triangles.size(), objectId);
  scene.materialIds.insert(scene.materialIds.end(), prim.triangles.size(), prim.material);
  transformRange(scene, world, vbase, tbase);
}

Scene buildScene(const GltfContext& ctx, const std::vector<NodeInstance>& instances, const PrimitiveCache& cache,
                 const std::vector<NodePose>& poses, GltfMaterials materials) {
  Scene scene;
  const bool uvs = materials.needsUvs();
  scene.materials = std::move(materials.materials);
  scene.alphaTextures = std::move(materials.textures);
  scene.alphaTexels = std::move(materials.texels);
  std::set<PrimitiveKey> warnedNormals;
  std::map<int, glm::dmat4> worlds;  // every flattened node's world matrix: skins' joints
  for (const NodeInstance& inst : instances) worlds.emplace(inst.node, inst.world);
  for (const NodeInstance& inst : instances) {
    const int mesh = ctx.model.nodes[static_cast<size_t>(inst.node)].mesh;
    if (mesh < 0) continue;
    const std::vector<double> weights = morphWeights(ctx, inst.node, poses[static_cast<size_t>(inst.node)]);
    const bool deformed = deforms(ctx, inst.node, weights);
    for (size_t p = 0; p < ctx.model.meshes[static_cast<size_t>(mesh)].primitives.size(); ++p) {
      const PrimitiveKey key{mesh, static_cast<int>(p)};
      const LocalPrimitive& read = cache.at(key);
      if (read.triangles.empty()) continue;
      LocalPrimitive own;  // this instance's shape when morphed or skinned
      glm::dmat4 world = inst.world;
      if (deformed) {
        own = read;
        if (deformPrimitive(ctx, inst, key.second, weights, worlds, own)) world = glm::dmat4(1.0);
      }
      const LocalPrimitive& prim = deformed ? own : read;
      const size_t vbase = scene.positions.size(), tbase = scene.triangles.size();
      appendInstance(scene, prim, world, static_cast<uint32_t>(scene.objectNames.size()), uvs);
      scene.objectNames.push_back(objectName(ctx.model, inst.node, mesh, key.second));
      const size_t repaired = repairNormals(scene, vbase, tbase);
      if (repaired > 0 && warnedNormals.insert(key).second)
        emitWarning(ctx.options, fmt::format("{}: mesh {} primitive {}: {} zero or non-finite normals replaced by "
                                             "face normals",
                                             ctx.file, key.first, key.second, repaired));
      for (size_t i = vbase; i < scene.positions.size(); ++i)
        if (const glm::vec3 q = scene.positions[i]; !inCoordinateRange(q.x, q.y, q.z))
          failGltf(ctx, fmt::format("node {} (mesh {} primitive {}): world position ({}, {}, {}) is outside +-{:g} "
                                    "(the renderer's coordinate range)",
                                    inst.node, mesh, key.second, q.x, q.y, q.z, kMaxCoordinate));
    }
  }
  return scene;
}

}  // namespace

Scene loadGltfResolved(const std::filesystem::path& path, const std::string& display, const LoadOptions& options,
                       FileReader& reader) {
  std::vector<unsigned char> bytes = reader.read(path);  // its errors name the path
  const ParsedGltf parsed = parseFile(bytes, path, display, options, reader);
  bytes = {};
  const GltfContext ctx{parsed.model, display, options};
  const std::vector<NodePose> poses = evaluateAnimations(ctx);
  const std::vector<NodeInstance> instances = flattenNodes(ctx, poses);
  const ImageSources images{parsed.dataUriImages, path.parent_path(), reader};
  GltfMaterials materials = readMaterials(ctx, images, usedMaterials(ctx, instances));
  const PrimitiveCache cache = readPrimitives(ctx, instances, materials);
  Scene scene = buildScene(ctx, instances, cache, poses, std::move(materials));
  scene.lights = readLights(ctx, instances);
  if (scene.triangles.empty()) failGltf(ctx, "no triangles (nothing in the scene can cast or receive shadows)");
  scene.cameras = readGltfCameras(ctx, instances);
  return scene;
}

}  // namespace detail

Scene loadGltf(const std::string& path, const LoadOptions& options) {
  detail::FileReader reader(options);
  return detail::loadGltfResolved(detail::resolveUserFile(path), path, options, reader);
}

}  // namespace penumbra
