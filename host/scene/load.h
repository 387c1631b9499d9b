// The one entry point tools use to get a scene: "builtin:NAME[:key=value,...]", a JSON scene file, or a
// .gltf / .glb model.
#pragma once

#include <string>

#include "host/scene/load_options.h"
#include "host/scene/scene.h"

namespace penumbra {

// Dispatches on the "builtin:" prefix or the file extension (case-insensitive: .json, .gltf, .glb).
// Throws SceneError for an unknown kind of scene, a missing file (naming the path), or bad content.
Scene loadScene(const std::string& spec, const LoadOptions& options = {});

}  // namespace penumbra
