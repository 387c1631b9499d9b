// The scene, camera, size and light options that `render` and `reference` share, and how they resolve: the
// command line first, else the scene file's, else a view framing the scene and a soft spot light above it.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "host/scene/framing.h"
#include "host/scene/scene.h"

namespace penumbra::cli {

struct ViewOptions {
  std::string scene, camera, size, light;
};

inline void addViewOptions(CLI::App* sub, ViewOptions& options) {
  sub->add_option("scene", options.scene, "Scene: a .gltf/.glb model, a .json scene file, or builtin:NAME")->required();
  sub->add_option("--camera", options.camera, "EX,EY,EZ:TX,TY,TZ[:FOVY_DEG] (default: the scene's or a framing view)");
  sub->add_option("--size", options.size, "Image size WxH (default: the scene's or 1280x720)");
  sub->add_option("--light", options.light,
                  "spot:PX,PY,PZ:TX,TY,TZ:FOV_DEG[:RADIUS] or dir:DX,DY,DZ[:ANGULAR_RADIUS_DEG]");
}

inline Camera resolveCamera(const ViewOptions& options, const Scene& scene) {
  Camera camera = options.camera.empty()
                      ? (scene.cameras.empty() ? framingCamera(scene.bounds()) : scene.cameras.front())
                      : parseCamera(options.camera);
  if (!options.size.empty()) parseSize(options.size, camera.width, camera.height);
  return camera;
}

inline Light resolveLight(const ViewOptions& options, const Scene& scene) {
  if (!options.light.empty()) return parseLight(options.light);
  return scene.lights.empty() ? framingLight(scene.bounds()) : scene.lights.front();
}

}  // namespace penumbra::cli
