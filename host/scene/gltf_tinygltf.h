// The one place that calls tinygltf (Debian's tiny_gltf.h 2.7): parsing with our own file-system
// callbacks (contained, capped, read-only), no image decoding (gltf_images.h decodes the few images alpha masks
// need), and errors turned into SceneError.
#pragma once

#include <tiny_gltf.h>

#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "host/scene/contained_fs.h"
#include "host/scene/load_options.h"

namespace penumbra::detail {

struct ParsedGltf {
  tinygltf::Model model;
  // The encoded bytes of every image given as a data: URI, by image index (tinygltf decodes the base64 and keeps no
  // URI for them). Images in buffer views are read from the buffer, external ones from their file, when needed.
  std::map<int, std::vector<unsigned char>> dataUriImages;
};

// Parses the first `size` bytes: a .gltf (binary == false) or a .glb whose container was already checked. External
// buffers are read through `reader`, relative to `root` and contained in it. Warnings go to options.warn.
ParsedGltf parseWithTinygltf(const std::vector<unsigned char>& bytes, size_t size, bool binary,
                             const std::filesystem::path& root, FileReader& reader, const std::string& file,
                             const LoadOptions& options);

// The struct tinygltf keeps for each element of the glTF's top-level array `array` ("accessors": sizeof(Accessor));
// 32 bytes (a string) for the others.
uint64_t tinygltfElementBytes(std::string_view array);

// A URI as tinygltf decodes buffer URIs before opening them (%XX escapes, '+' as a space), for image URIs alike.
std::string decodeUri(const std::string& uri);

}  // namespace penumbra::detail
