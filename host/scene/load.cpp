// Scene loading dispatch: built-in scenes by name, everything else by file extension (checked before the
// file system is touched, so "scene.obj" gets the "unknown kind" message); and the default warning sink.
#include "host/scene/load.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <iostream>

#include <fmt/format.h>

#include "host/scene/gltf_loader.h"
#include "host/scene/light_names.h"
#include "host/scene/procedural.h"
#include "host/scene/scene_file.h"

namespace penumbra {

void emitWarning(const LoadOptions& options, const std::string& message) {
  if (options.warn)
    options.warn(message);
  else
    std::cerr << "warning: " << message << '\n';
}

Scene loadScene(const std::string& spec, const LoadOptions& options) {
  constexpr std::string_view kBuiltin = "builtin:";
  if (spec.rfind(kBuiltin, 0) == 0) {
    Scene scene = makeProceduralFromSpec(std::string_view(spec).substr(kBuiltin.size()));
    nameLights(scene.lights);  // "light0", ...: every scene's lights have channel-safe names
    return scene;
  }
  std::string ext = std::filesystem::path(spec).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext != ".json" && ext != ".gltf" && ext != ".glb")
    throw SceneError(
        fmt::format("{}: unknown kind of scene (expected builtin:NAME, a .json scene file, or a .gltf "
                    "or .glb model)",
                    spec));
  detail::FileReader reader(options);
  const std::filesystem::path path = detail::resolveUserFile(spec);
  if (ext == ".json") return detail::loadSceneFileResolved(path, spec, options, reader);
  return detail::loadGltfResolved(path, spec, options, reader);
}

}  // namespace penumbra
