// pn_scene, pn_camera and pn_light: loading (host/scene/load.h), the plain structs' defaults and command-line forms,
// and the defaults a frame falls back to (host/scene/framing.h), as the CLI resolves them.
#include <fmt/format.h>

#include <cstdint>
#include <glm/gtc/type_ptr.hpp>
#include <vector>

#include "api/convert.h"
#include "api/guard.h"
#include "api/handles.h"
#include "host/scene/framing.h"
#include "host/scene/load.h"
#include "host/scene/mesh_input.h"

using penumbra::api::guard;
using penumbra::api::require;

namespace {

const pn_scene& sceneArg(const pn_scene* scene, const char* function) { return *require(scene, function, "scene"); }

void checkIndex(size_t index, size_t count, const char* function, const char* what) {
  if (index >= count)
    throw std::out_of_range(
        fmt::format("{}: {} index {} out of range (the scene has {})", function, what, index, count));
}

// A pn_mesh as the scene layer's MeshInput (spans over the caller's arrays, read during pn_scene_create only).
penumbra::MeshInput meshInput(const pn_mesh& mesh, size_t index) {
  const std::string what = fmt::format("pn_scene_create: meshes[{}]", index);
  penumbra::api::requireSized(&mesh, sizeof(pn_mesh), "pn_scene_create", fmt::format("meshes[{}]", index).c_str(),
                              "pn_mesh_init");
  if (mesh.vertex_count > SIZE_MAX / 3 || mesh.triangle_count > SIZE_MAX / 3)
    throw std::invalid_argument(what + ": vertex or triangle count overflows");
  if (mesh.vertex_count > 0) require(mesh.positions, what.c_str(), "positions");
  if (mesh.triangle_count > 0) require(mesh.indices, what.c_str(), "indices");
  penumbra::MeshInput input;
  input.positions = {mesh.positions, 3 * mesh.vertex_count};
  if (mesh.normals != nullptr) input.normals = {mesh.normals, 3 * mesh.vertex_count};
  input.indices = {mesh.indices, 3 * mesh.triangle_count};
  if (mesh.transform != nullptr) input.transform = glm::make_mat4(mesh.transform);
  input.name = mesh.name != nullptr ? mesh.name : "";
  input.doubleSided = mesh.double_sided != 0;
  return input;
}

}  // namespace

extern "C" {

void pn_camera_init(pn_camera* camera) {
  if (camera != nullptr) *camera = penumbra::api::toC(penumbra::Camera{});
}

pn_status pn_camera_parse(const char* spec, pn_camera* camera) {
  return guard([&] {
    require(camera, "pn_camera_parse", "camera");
    penumbra::api::fill(penumbra::parseCamera(require(spec, "pn_camera_parse", "spec")), camera, "pn_camera_parse",
                        "camera");
  });
}

void pn_light_init(pn_light* light) {
  if (light != nullptr) {
    static const penumbra::Light kDefault;  // its name ("") outlives every pn_light
    *light = penumbra::api::toC(kDefault);
    light->name = nullptr;
  }
}

pn_status pn_light_parse(const char* spec, pn_light* light) {
  return guard([&] {
    require(light, "pn_light_parse", "light");
    penumbra::api::fill(penumbra::parseLight(require(spec, "pn_light_parse", "spec")), light, "pn_light_parse",
                        "light");
    light->name = nullptr;  // a parsed light is unnamed
  });
}

void pn_scene_load_options_init(pn_scene_load_options* options) {
  if (options != nullptr) *options = pn_scene_load_options{sizeof(pn_scene_load_options), 0, 0.0, nullptr};
}

pn_status pn_scene_load(const char* spec, const pn_scene_load_options* options, pn_scene** scene) {
  return guard([&] {
    require(scene, "pn_scene_load", "scene");
    require(spec, "pn_scene_load", "spec");
    penumbra::LoadOptions load;
    if (options != nullptr)
      penumbra::api::requireSized(options, sizeof(pn_scene_load_options), "pn_scene_load", "options",
                                  "pn_scene_load_options_init");
    if (options != nullptr && options->has_time != 0) load.time = options->time;
    if (options != nullptr && options->animation != nullptr) load.animation = options->animation;
    auto loaded = std::make_unique<pn_scene>();
    loaded->scene = penumbra::loadScene(spec, load);
    loaded->spec = spec;
    *scene = loaded.release();
  });
}

void pn_mesh_init(pn_mesh* mesh) {
  if (mesh != nullptr) *mesh = pn_mesh{sizeof(pn_mesh), nullptr, 0, nullptr, nullptr, 0, nullptr, nullptr, 1};
}

pn_status pn_scene_create(const pn_mesh* meshes, size_t mesh_count, const pn_light* lights, size_t light_count,
                          pn_scene** scene) {
  return guard([&] {
    require(scene, "pn_scene_create", "scene");
    if (mesh_count > 0) require(meshes, "pn_scene_create", "meshes");
    if (light_count > 0) require(lights, "pn_scene_create", "lights");
    std::vector<penumbra::MeshInput> inputs;
    for (size_t i = 0; i < mesh_count; ++i) inputs.push_back(meshInput(meshes[i], i));
    std::vector<penumbra::Light> sceneLights;
    for (size_t i = 0; i < light_count; ++i)
      sceneLights.push_back(penumbra::api::fromC(lights[i], "pn_scene_create", fmt::format("lights[{}]", i).c_str()));
    auto created = std::make_unique<pn_scene>();
    created->scene = penumbra::meshScene(inputs, std::move(sceneLights));
    created->spec = fmt::format("meshes ({} meshes, {} triangles)", mesh_count, created->scene.triangleCount());
    *scene = created.release();
  });
}

pn_status pn_scene_retain(pn_scene* scene) { return penumbra::api::retainHandle(scene, "pn_scene_retain"); }

pn_status pn_scene_release(pn_scene* scene) { return penumbra::api::releaseHandle(scene); }

size_t pn_scene_triangle_count(const pn_scene* scene) { return scene != nullptr ? scene->scene.triangleCount() : 0; }

pn_status pn_scene_bounds(const pn_scene* scene, float min[3], float max[3]) {
  return guard([&] {
    const penumbra::Bounds bounds = sceneArg(scene, "pn_scene_bounds").scene.bounds();
    float* lo = require(min, "pn_scene_bounds", "min");
    float* hi = require(max, "pn_scene_bounds", "max");
    for (int i = 0; i < 3; ++i) lo[i] = bounds.min[i], hi[i] = bounds.max[i];
  });
}

size_t pn_scene_camera_count(const pn_scene* scene) { return scene != nullptr ? scene->scene.cameras.size() : 0; }

pn_status pn_scene_camera(const pn_scene* scene, size_t index, pn_camera* camera) {
  return guard([&] {
    const auto& cameras = sceneArg(scene, "pn_scene_camera").scene.cameras;
    checkIndex(index, cameras.size(), "pn_scene_camera", "camera");
    penumbra::api::fill(cameras[index], camera, "pn_scene_camera", "camera");
  });
}

pn_status pn_scene_default_camera(const pn_scene* scene, pn_camera* camera) {
  return guard([&] {
    const penumbra::Scene& s = sceneArg(scene, "pn_scene_default_camera").scene;
    require(camera, "pn_scene_default_camera", "camera");
    penumbra::api::fill(s.cameras.empty() ? penumbra::framingCamera(s.bounds()) : s.cameras.front(), camera,
                        "pn_scene_default_camera", "camera");
  });
}

size_t pn_scene_light_count(const pn_scene* scene) { return scene != nullptr ? scene->scene.lights.size() : 0; }

pn_status pn_scene_light(const pn_scene* scene, size_t index, pn_light* light) {
  return guard([&] {
    const auto& lights = sceneArg(scene, "pn_scene_light").scene.lights;
    checkIndex(index, lights.size(), "pn_scene_light", "light");
    penumbra::api::fill(lights[index], light, "pn_scene_light", "light");
  });
}

pn_status pn_scene_framing_light(const pn_scene* scene, pn_light* light) {
  return guard([&] {
    const penumbra::Scene& s = sceneArg(scene, "pn_scene_framing_light").scene;
    require(light, "pn_scene_framing_light", "light");
    penumbra::api::fill(penumbra::framingLight(s.bounds()), light, "pn_scene_framing_light", "light");
    light->name = nullptr;
  });
}

}  // extern "C"
