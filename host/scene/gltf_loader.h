// Loading .gltf and .glb files into a flattened, world-space Scene (tinygltf for parsing; all validation,
// hierarchy flattening and triangulation here).
#pragma once

#include <filesystem>
#include <string>

#include "host/scene/contained_fs.h"
#include "host/scene/load_options.h"
#include "host/scene/scene.h"

namespace penumbra {

// Loads the default scene (or scene 0, or every root node when the file has no scenes): one object per
// mesh-primitive instance, named "node/mesh/primitive" (names, or indices where unnamed). Buffers must lie
// inside the file's folder. Throws SceneError naming the file and element for bad or unsupported input,
// including "no triangles". Every camera instance of that scene becomes one of Scene::cameras (gltf_camera.h);
// its lights (KHR_lights_punctual) come in Scene::lights, in node order (gltf_lights.h).
Scene loadGltf(const std::string& path, const LoadOptions& options = {});

namespace detail {
// The same for a path already resolved (canonical), sharing `reader`'s byte budget; `display` names the
// file in messages.
Scene loadGltfResolved(const std::filesystem::path& path, const std::string& display, const LoadOptions& options,
                       FileReader& reader);
}  // namespace detail

}  // namespace penumbra
