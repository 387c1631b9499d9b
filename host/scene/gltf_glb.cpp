// GLB header and chunk validation (glTF 2.0 spec, section 4.4 "Binary glTF Layout"). Lengths are checked
// in 64-bit arithmetic, so no chunk length can wrap an offset.
#include "host/scene/gltf_glb.h"

#include <cstdint>
#include <cstring>

#include <fmt/format.h>

#include "host/scene/load_options.h"

namespace penumbra::detail {
namespace {

constexpr uint32_t kChunkJson = 0x4E4F534A;  // "JSON", little endian
constexpr uint32_t kChunkBin = 0x004E4942;   // "BIN\0", little endian

uint32_t readU32(const std::vector<unsigned char>& bytes, uint64_t offset) {
  return uint32_t{bytes[offset]} | uint32_t{bytes[offset + 1]} << 8 | uint32_t{bytes[offset + 2]} << 16 |
         uint32_t{bytes[offset + 3]} << 24;
}

}  // namespace

bool hasGlbMagic(const std::vector<unsigned char>& bytes) {
  return bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
}

GlbChunks parseGlb(const std::vector<unsigned char>& bytes, const std::string& file) {
  const auto fail = [&](const std::string& msg) { throw SceneError(fmt::format("{}: GLB: {}", file, msg)); };
  if (bytes.size() < 12) fail(fmt::format("file is {} bytes, shorter than the 12-byte header", bytes.size()));
  if (!hasGlbMagic(bytes)) fail("bad magic (not a binary glTF file)");
  if (const uint32_t version = readU32(bytes, 4); version != 2)
    fail(fmt::format("container version {} is not supported (2 only)", version));
  const uint64_t length = readU32(bytes, 8);
  if (length > bytes.size() || length < 12)
    fail(fmt::format("header says {} bytes but the file has {}", length, bytes.size()));

  GlbChunks chunks;
  bool haveJson = false;
  for (uint64_t offset = 12, index = 0; offset < length; ++index) {
    if (offset + 8 > length) fail(fmt::format("chunk {} header at byte {} is truncated", index, offset));
    const uint64_t chunkLength = readU32(bytes, offset);
    const uint32_t type = readU32(bytes, offset + 4);
    if (offset + 8 + chunkLength > length)
      fail(fmt::format("chunk {} at byte {}: length {} runs past the end of the file ({} bytes)", index, offset,
                       chunkLength, length));
    if (chunkLength % 4 != 0) fail(fmt::format("chunk {}: length {} is not a multiple of 4", index, chunkLength));
    const auto* data = reinterpret_cast<const char*>(bytes.data() + offset + 8);
    if (index == 0) {
      if (type != kChunkJson) fail(fmt::format("chunk 0 has type 0x{:08x}, expected JSON", type));
      if (chunkLength == 0) fail("JSON chunk is empty");
      chunks.json = std::string_view(data, chunkLength);
      haveJson = true;
      // Sec. 4.4.3.2: the JSON is UTF-8 without a byte-order mark, padded to 4 bytes with spaces (0x20).
      if (chunks.json.substr(0, 3) == "\xef\xbb\xbf") fail("the JSON chunk starts with a byte-order mark");
      const size_t end = chunks.json.find_last_not_of(" \t\r\n");
      if (end != std::string_view::npos && chunks.json[end] == '\0')
        fail("the JSON chunk is padded with 0x00 bytes; glTF pads it with spaces (0x20)");
    } else if (index == 1 && type == kChunkBin) {
      chunks.binSize = chunkLength;
    } else if (type == kChunkJson || type == kChunkBin) {
      fail(fmt::format("chunk {} is a second {} chunk or out of order", index, type == kChunkJson ? "JSON" : "BIN"));
    }  // chunks of other types are allowed by the spec and ignored
    offset += 8 + chunkLength;
  }
  if (!haveJson) fail("no JSON chunk");
  chunks.length = length, chunks.trailing = bytes.size() - length;
  return chunks;
}

}  // namespace penumbra::detail
