// The alpha channel of a glTF image (glTF 2.0 sec. 3.8.2 "Images"), for alpha-tested materials only: its encoded
// bytes from a buffer view, a data: URI or a file inside the model's folder (resolveInside, through the load's
// FileReader), decoded with Debian's stb_image, keeping one byte per texel.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "host/scene/contained_fs.h"
#include "host/scene/gltf_accessor.h"

namespace penumbra::detail {

// Where a file's images come from besides its buffers.
struct ImageSources {
  const std::map<int, std::vector<unsigned char>>& dataUri;  // ParsedGltf::dataUriImages
  std::filesystem::path root;                                // the model's folder (canonical)
  FileReader& reader;                                        // the load's file and texture budgets
};

struct DecodedAlpha {
  uint32_t width = 0, height = 0;
  bool hasAlpha = false;        // false: the image has no alpha channel (alpha 1 everywhere); no texels kept
  std::vector<uint8_t> texels;  // width * height alpha values, the image's top row first (hasAlpha only)
};

// "image 3 \"leaves.png\"" (its name, else its URI, else nothing): how messages name an image.
std::string imageLabel(const GltfContext& ctx, int image);

// Decodes image `image` (an index checked by the schema). Images without an alpha channel are read to their header
// only. Throws SceneError "FILE: image N "NAME": ..." when its file is missing or outside the folder, its buffer view
// runs past its buffer, it cannot be decoded, or its texels exceed the load's texture budget (claimed here).
DecodedAlpha decodeImageAlpha(const GltfContext& ctx, const ImageSources& sources, int image);

}  // namespace penumbra::detail
