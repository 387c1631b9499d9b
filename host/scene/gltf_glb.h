// The binary glTF container (GLB): a 12-byte header, a JSON chunk and an optional BIN chunk. Checked here
// in full before tinygltf reads it, so that every bad length gets a message that names it.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace penumbra::detail {

bool hasGlbMagic(const std::vector<unsigned char>& bytes);

struct GlbChunks {
  std::string_view json;
  size_t binSize = 0;  // 0: no BIN chunk
};

// Throws SceneError "FILE: GLB ..." for a short file, wrong magic or version, a header length that is not
// the file size, a chunk that runs past the end or is not 4-byte aligned, or a missing/misplaced JSON or
// BIN chunk.
GlbChunks parseGlb(const std::vector<unsigned char>& bytes, const std::string& file);

}  // namespace penumbra::detail
