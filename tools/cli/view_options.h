// The scene, camera, size, light and material options that `render`, `reference` and `bench` share, and how they
// resolve: the command line first, else the scene's (a scene file's or a glTF file's lights: all of them), else a view
// framing the scene and a soft spot light above it.
#pragma once

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdlib>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>

#include "host/io/image.h"
#include "host/pipeline/memory_plan.h"
#include "host/scene/framing.h"
#include "host/scene/light_names.h"
#include "host/scene/load.h"
#include "host/scene/load_options.h"
#include "host/scene/scene.h"

namespace penumbra::cli {

struct ViewOptions {
  std::string scene, camera, size, light;
  double time = 0.0;  // with timeGiven: glTF animations at this time (seconds)
  bool timeGiven = false;
  std::string animation;
  float blendCutoff = LoadOptions{}.blendCutoff;  // alphaMode BLEND's cutoff (drawn as MASK)
  std::string memoryLimit;  // --memory-limit: a frame's plan above it is refused (host/pipeline/memory_plan.h)
};

// --memory-limit as bytes (none when not given); a bad value is a usage error.
inline std::optional<uint64_t> memoryLimit(const ViewOptions& options) {
  if (options.memoryLimit.empty()) return std::nullopt;
  return parseMemorySize(options.memoryLimit, "--memory-limit");
}

inline void addViewOptions(CLI::App* sub, ViewOptions& options) {
  sub->add_option("scene", options.scene, "Scene: a .gltf/.glb model, a .json scene file, or builtin:NAME")->required();
  sub->add_option("--camera", options.camera,
                  "EX,EY,EZ:TX,TY,TZ[:FOVY_DEG] or gltf:INDEX|NAME (default: the scene's first camera, glTF "
                  "cameras included, or a framing view)");
  sub->add_option("--size", options.size,
                  "Image size WxH (default: the camera's: a glTF camera's 720 high at its aspect ratio, else "
                  "1280x720)");
  sub->add_option("--light", options.light,
                  "spot:PX,PY,PZ:TX,TY,TZ:FOV_DEG[:RADIUS], dir:DX,DY,DZ[:ANGULAR_RADIUS_DEG], point:PX,PY,PZ[:RADIUS] "
                  "or gltf:INDEX|NAME, one of the scene's lights: one light instead of the default, every light of "
                  "the scene (or a framing spot light when it has none)");
  CLI::Option* time =
      sub->add_option_function<double>(
             "--time", [&options](double t) { options.time = t, options.timeGiven = true; },
             "Seconds: glTF animations (node transforms, skins, morph weights) evaluated at this time, each held at "
             "its first or last key outside its range (default: the file's static pose)")
          ->check(CLI::Number);
  sub->add_option("--animation", options.animation,
                  "With --time: the one glTF animation to play, by index or name (default: every animation)")
      ->needs(time);
  sub->add_option("--blend-cutoff", options.blendCutoff,
                  "Alpha cutoff of glTF alphaMode BLEND materials, which are drawn as MASK (shadows have no "
                  "translucency)")
      ->check(CLI::Range(0.0f, 1.0f))
      ->check(CLI::Validator(
          [](std::string& text) {  // CLI::Range lets NaN through (every comparison with it is false)
            const float value = std::strtof(text.c_str(), nullptr);
            return std::isfinite(value) ? std::string() : "not a number in [0, 1]";
          },
          "FINITE"))
      ->capture_default_str();
  sub->add_option("--memory-limit", options.memoryLimit,
                  "Refuse a frame whose memory plan needs more device or host memory than this (4GiB, 512MiB, ...; "
                  "default: the device's global memory)");
}

// The scene as the command line loads it, for EXR provenance and cache keys: the spec, then --time and --animation
// when given ("walk.glb --time 0.5 --animation Run").
inline std::string sceneProvenance(const ViewOptions& options) {
  if (!options.timeGiven) return options.scene;
  return fmt::format("{} --time {}{}", options.scene, options.time,
                     options.animation.empty() ? "" : " --animation " + options.animation);
}

// The scene loader's options these view options ask for (--time, --animation, --blend-cutoff).
inline LoadOptions loadOptions(const ViewOptions& options) {
  LoadOptions load;
  if (options.timeGiven) load.time = options.time;
  load.animation = options.animation;
  load.blendCutoff = options.blendCutoff;
  return load;
}

// The scene the options name, loaded with their loader options.
inline Scene loadViewScene(const ViewOptions& options) { return loadScene(options.scene, loadOptions(options)); }

// The materials line of the tools' summaries and the EXR header's penumbra:materials ("" without materials).
inline void recordMaterials(const Scene& scene, Image& image) {
  const std::string materials = describeMaterials(scene);
  if (materials.empty()) return;
  image.attributes()["penumbra:materials"] = materials;
  image.numbers()["penumbra:alpha-texture-bytes"] = static_cast<double>(scene.alphaTexels.size());
}

// --camera gltf:KEY (findGltfCamera), --camera EX,..., else the scene's first camera, else the framing view. --size
// replaces the camera's size; a glTF camera keeps its vertical fov (or ymag) and takes the image's aspect ratio.
inline Camera resolveCamera(const ViewOptions& options, const Scene& scene) {
  Camera camera;
  if (options.camera.rfind("gltf:", 0) == 0) {
    try {
      camera = findGltfCamera(scene, std::string_view(options.camera).substr(5));
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("--camera " + options.camera + ": " + e.what());
    }
  } else {
    camera = options.camera.empty() ? (scene.cameras.empty() ? framingCamera(scene.bounds()) : scene.cameras.front())
                                    : parseCamera(options.camera);
  }
  if (!options.size.empty()) parseSize(options.size, camera.width, camera.height);
  return camera;
}

// Which camera resolveCamera took, for the summary: "gltf:0 \"Main\" (perspective)", "--camera", "the scene's"
// or "a framing view", then its describe().
inline std::string cameraSummary(const ViewOptions& options, const Scene& scene, const Camera& camera) {
  std::string source = camera.label();
  if (source.empty())
    source = !options.camera.empty() ? "--camera" : scene.cameras.empty() ? "a framing view" : "the scene's";
  return source + ", " + camera.describe();
}

inline constexpr std::string_view kSceneLightPrefix = "gltf:";  // --light gltf:INDEX|NAME

// The frame's lights: --light gltf:KEY, that one of the scene's; --light SPEC, that light (unnamed: its EXR layer is
// kUnnamedLightLayer, "light"); else every light of the scene (their names unique and channel-safe), else the
// framing light (unnamed too).
inline std::vector<Light> resolveLights(const ViewOptions& options, const Scene& scene) {
  if (options.light.rfind(kSceneLightPrefix, 0) == 0)
    return {scene.lights[findLight(scene.lights, std::string_view(options.light).substr(kSceneLightPrefix.size()))]};
  if (!options.light.empty()) return {parseLight(options.light)};
  if (scene.lights.empty()) return {framingLight(scene.bounds())};
  return scene.lights;
}

// Which lights resolveLights chose and why, one line each, for the summary: "light \"Key\" (the scene's 1 of 2):
// spot:...", "light \"Sun\" (--light gltf:Sun): dir:...", "light (--light): dir:...".
inline std::string describeLightChoice(const ViewOptions& options, const Scene& scene,
                                       const std::vector<Light>& lights) {
  std::string lines;
  for (size_t i = 0; i < lights.size(); ++i) {
    std::string origin;
    if (options.light.rfind(kSceneLightPrefix, 0) == 0)
      origin = "--light " + options.light;
    else if (!options.light.empty())
      origin = "--light";
    else if (!scene.lights.empty())
      origin = fmt::format("the scene's {} of {}", i + 1, scene.lights.size());
    else
      origin = "framing the scene, which has no lights";
    const Light& light = lights[i];
    lines += fmt::format("{}light{} ({}): {}", lines.empty() ? "" : "\n",
                         light.name.empty() ? "" : " \"" + light.name + "\"", origin, light.describe());
  }
  return lines;
}

}  // namespace penumbra::cli
