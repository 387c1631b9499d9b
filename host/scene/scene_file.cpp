// Composition of a JSON scene: models (loaded, then placed), built-in scenes, the ground plane sized from
// everything before it, then the views. Errors from a model's own file are wrapped with the pointer of
// the model entry that named it.
#include "host/scene/scene_file.h"

#include <cmath>

#include <fmt/format.h>

#include "host/scene/gltf_loader.h"
#include "host/scene/json_util.h"
#include "host/scene/limits.h"
#include "host/scene/light_names.h"
#include "host/scene/procedural.h"
#include "host/scene/procedural_mesh.h"
#include "host/scene/scene_file_parts.h"

namespace penumbra::detail {
namespace {

struct FileContext {
  const std::filesystem::path& folder;
  const std::string& file;
  const LoadOptions& options;
  FileReader& reader;
};

// Calls fn(element, pointer) for each element of root[key], which must be an array.
template <class Fn>
void forEach(ObjectReader& root, const char* key, Fn fn) {
  const Json* list = root.find(key);
  if (!list) return;
  if (!list->is_array()) root.fail(key, "expected an array");
  for (size_t i = 0; i < list->size(); ++i) fn((*list)[i], pointerTo(root.pointer(key), i));
}

bool isGltfPath(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".gltf" || ext == ".glb";
}

// The model's own lights (KHR_lights_punctual) move with it; like glTF's node scale, the placement's scale changes
// no light's size, cone or range.
void placeLights(const FileContext& ctx, Scene& model, const glm::mat4& placement, const std::string& pointer) {
  const auto finite = [](const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
  for (Light& light : model.lights) {
    light.position = glm::vec3(placement * glm::vec4(light.position, 1.0f));
    light.target = glm::vec3(placement * glm::vec4(light.target, 1.0f));
    const glm::vec3 d = glm::mat3(placement) * light.direction;
    light.direction = d / glm::length(d);
    if (!finite(light.position) || !finite(light.target) || !finite(light.direction) ||
        (light.type == LightType::Spot && light.position == light.target))
      failAt(ctx.file, pointer, fmt::format("placed light \"{}\" overflows (scale too large?)", light.name));
  }
}

Scene readModel(const FileContext& ctx, const Json& value, const std::string& pointer) {
  ObjectReader r(value, ctx.file, pointer);
  const std::string path = r.string("path");
  if (!isGltfPath(path)) r.fail("path", fmt::format("\"{}\" is not a .gltf or .glb file", path));
  const glm::mat4 placement = readPlacement(r);
  r.finish();
  std::filesystem::path resolved;
  try {
    resolved = resolveSceneModel(ctx.folder, path);
  } catch (const SceneError& e) {
    r.fail("path", e.what());
  }
  Scene model;
  try {
    model = loadGltfResolved(resolved, path, ctx.options, ctx.reader);
  } catch (const SceneError& e) {
    failAt(ctx.file, pointer, e.what());
  }
  transformGeometry(model, placement);
  transformCameras(model, placement);
  for (const glm::vec3& p : model.positions)
    if (!inCoordinateRange(p.x, p.y, p.z))
      failAt(ctx.file, pointer,
             fmt::format("placed geometry reaches ({}, {}, {}), outside +-{:g} (the renderer's coordinate range; "
                         "scale too large?)",
                         p.x, p.y, p.z, kMaxCoordinate));
  placeLights(ctx, model, placement, pointer);
  return model;
}

// A "procedural" entry's name and parameters, then `make(name, params)` (makeProcedural, or
// proceduralTriangleCount to check the file before building), its errors named with the entry's pointer.
template <class Make>
auto readProcedural(const FileContext& ctx, const Json& value, const std::string& pointer, Make make) {
  ObjectReader r(value, ctx.file, pointer);
  const std::string name = r.string("name");
  ProceduralParams params;
  for (auto it = value.begin(); it != value.end(); ++it) {
    if (it.key() == "name") continue;
    if (!it.value().is_number()) r.fail(it.key(), "expected a number, got " + brief(it.value()));
    params[it.key()] = it.value().get<double>();
  }
  try {
    return make(name, params);
  } catch (const SceneError& e) {
    failAt(ctx.file, pointer, e.what());
  }
}

// Fails, naming the limit, when `triangles` (built and about to be built) exceed LoadOptions::maxTriangles.
void checkTriangles(const FileContext& ctx, uint64_t triangles, const std::string& pointer, const char* what) {
  if (triangles > ctx.options.maxTriangles)
    failAt(ctx.file, pointer,
           fmt::format("{} make {} triangles, more than the limit of {} per load (LoadOptions::maxTriangles)", what,
                       triangles, ctx.options.maxTriangles));
}

// The keys a scene file may have at its top level (the readers below ask for each).
constexpr const char* kTopLevelKeys[] = {"models", "procedural", "ground", "camera", "cameras", "lights"};

void readGround(const FileContext& ctx, ObjectReader& root, Scene& scene) {
  const Json* value = root.find("ground");
  if (!value) return;
  ObjectReader r(*value, ctx.file, root.pointer("ground"));
  const bool enabled = r.boolean("enabled", true);
  const auto margin = static_cast<float>(r.number("margin", 0, 1000, "[0, 1000]", 1.0));
  const Bounds bounds = scene.bounds();
  const Json* y = r.find("y");
  if (y && (!y->is_number() || !inCoordinateRange(y->get<double>())))
    r.fail("y", fmt::format("expected a number in +-{:g} (the renderer's coordinate range), got {}", kMaxCoordinate,
                            brief(*y)));
  r.finish();
  if (!enabled) return;
  if (bounds.empty()) failAt(ctx.file, root.pointer("ground"), "no models or built-in scenes to place a ground under");
  addGroundPlane(scene, bounds, margin, y ? static_cast<float>(y->get<double>()) : bounds.min.y);
}

// "camera": "gltf:INDEX|NAME" picks one of the models' glTF cameras (indices count across models, in order).
Camera chooseModelCamera(ObjectReader& root, const Json& value, const Scene& scene) {
  const std::string spec = value.get<std::string>();
  if (spec.rfind("gltf:", 0) != 0)
    root.fail("camera", fmt::format("expected a camera object or \"gltf:INDEX|NAME\", got \"{}\"", spec));
  try {
    return findGltfCamera(scene, std::string_view(spec).substr(5));
  } catch (const std::invalid_argument& e) {
    root.fail("camera", e.what());
  }
}

// Entries with a "type" define lights, which replace those the models and built-in scenes bring; entries without
// one set the size of a light the models bring, by name (after the names are made unique across the models).
void readSceneLights(const FileContext& ctx, ObjectReader& root, Scene& scene) {
  std::vector<Light> lights;
  std::vector<std::pair<const Json*, std::string>> sizes;
  forEach(root, "lights", [&](const Json& v, const std::string& p) {
    if (v.is_object() && !v.contains("type"))
      sizes.emplace_back(&v, p);
    else
      lights.push_back(readLight(v, ctx.file, p));
  });
  if (root.has("lights") && lights.empty() && sizes.empty())
    root.fail("lights", "is empty (leave it out to keep the built-in scenes' lights)");
  if (!lights.empty() && !sizes.empty())
    failAt(ctx.file, sizes.front().second,
           "sets the size of a model's light, but the file also defines lights (with \"type\"), which replace the "
           "models' lights");
  if (!lights.empty()) scene.lights = std::move(lights);
  nameLights(scene.lights);
  for (const auto& [value, pointer] : sizes) readLightSize(*value, ctx.file, pointer, scene.lights);
}

// Cameras given here come first (the default) and replace the built-in scenes'; the models' glTF cameras stay
// behind them for --camera gltf:.
void readViews(const FileContext& ctx, ObjectReader& root, Scene& scene) {
  std::vector<Camera> cameras;
  if (const Json* c = root.find("camera"))
    cameras.push_back(c->is_string() ? chooseModelCamera(root, *c, scene)
                                     : readCamera(*c, ctx.file, root.pointer("camera")));
  forEach(root, "cameras", [&](const Json& v, const std::string& p) { cameras.push_back(readCamera(v, ctx.file, p)); });
  if (!cameras.empty()) {
    const int chosen = cameras.front().gltfIndex;  // "gltf:..." moved to the front, not listed twice
    for (const Camera& c : scene.cameras)
      if (c.gltfIndex >= 0 && c.gltfIndex != chosen) cameras.push_back(c);
    scene.cameras = std::move(cameras);
  }
  readSceneLights(ctx, root, scene);
}

}  // namespace

Scene loadSceneFileResolved(const std::filesystem::path& path, const std::string& display, const LoadOptions& options,
                            FileReader& reader) {
  std::vector<unsigned char> bytes = reader.read(path);  // its errors name the path
  const Json doc = parseJson(display, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), true,
                             options.maxJsonValues);
  const std::filesystem::path folder = path.parent_path();
  const FileContext ctx{folder, display, options, reader};
  ObjectReader root(doc, display, "");
  // The whole file is checked before any geometry is built: its top-level keys, then every built-in scene's name,
  // parameters and triangle count against the limit (eight 1000x1000 poles used to build 96 M triangles, 8 GB, and
  // a misspelled key came out after 12 M of them).
  for (const char* key : kTopLevelKeys) root.find(key);
  root.finish();
  uint64_t procedural = 0;
  forEach(root, "procedural", [&](const Json& v, const std::string& p) {
    procedural += readProcedural(ctx, v, p, [](std::string_view name, const ProceduralParams& params) {
      return proceduralTriangleCount(name, params);
    });
  });
  checkTriangles(ctx, procedural, "/procedural", "the built-in scenes");
  Scene scene;
  forEach(root, "models", [&](const Json& v, const std::string& p) {
    scene.append(readModel(ctx, v, p));
    checkTriangles(ctx, scene.triangles.size() + procedural, p, "the models so far and the built-in scenes");
  });
  forEach(root, "procedural", [&](const Json& v, const std::string& p) {
    scene.append(readProcedural(ctx, v, p, [](std::string_view name, const ProceduralParams& params) {
      return makeProcedural(name, params);
    }));
  });
  readGround(ctx, root, scene);
  readViews(ctx, root, scene);
  root.finish();
  if (scene.triangles.empty()) failAt(display, "", "no triangles (add \"models\" or \"procedural\")");
  return scene;
}

}  // namespace penumbra::detail

namespace penumbra {

Scene loadSceneFile(const std::string& path, const LoadOptions& options) {
  detail::FileReader reader(options);
  return detail::loadSceneFileResolved(detail::resolveUserFile(path), path, options, reader);
}

}  // namespace penumbra
