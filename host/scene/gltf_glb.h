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
  size_t binSize = 0;   // 0: no BIN chunk
  size_t length = 0;    // the header's length: the container's bytes
  size_t trailing = 0;  // bytes after it (allowed, ignored: the caller warns)
};

// Throws SceneError "FILE: GLB ..." for a short file, wrong magic or version, a header length beyond the file
// size, a chunk that runs past the end or is not 4-byte aligned, a missing/misplaced JSON or BIN chunk, or a JSON
// chunk that starts with a byte-order mark or is padded with anything but spaces (sec. 4.4.3.2).
GlbChunks parseGlb(const std::vector<unsigned char>& bytes, const std::string& file);

}  // namespace penumbra::detail
