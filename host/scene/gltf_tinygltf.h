// The one place that calls tinygltf (Debian's tiny_gltf.h 2.7): parsing with our own file-system
// callbacks (contained, capped, read-only), no image decoding, and errors turned into SceneError.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <tiny_gltf.h>

#include "host/scene/contained_fs.h"
#include "host/scene/load_options.h"

namespace penumbra::detail {

// Parses a .gltf (binary == false) or a .glb whose container was already checked. External buffers are
// read through `reader`, relative to `root` and contained in it. Warnings go to options.warn.
tinygltf::Model parseWithTinygltf(const std::vector<unsigned char>& bytes, bool binary,
                                  const std::filesystem::path& root, FileReader& reader, const std::string& file,
                                  const LoadOptions& options);

}  // namespace penumbra::detail
