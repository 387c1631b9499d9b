// What every scene loader shares: the error type for bad input (messages name the file and the element)
// and the limits and warning sink a caller passes in.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>

namespace penumbra {

// Bad or unsupported input: "scene.gltf: accessor 12: index 7071 out of range (vertex count 512)".
class SceneError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

using WarningSink = std::function<void(const std::string&)>;
// Sees every file a load reads, in order, with its bytes (`penumbra plan` and `run` hash a scene's content).
using FileReadSink = std::function<void(const std::filesystem::path&, std::span<const unsigned char>)>;

struct LoadOptions {
  uint64_t maxFileBytes = uint64_t{1} << 30;   // per file read (.gltf, .glb, .bin, .json)
  uint64_t maxTotalBytes = uint64_t{4} << 30;  // all files one load reads, together
  uint64_t maxTriangles = uint64_t{1} << 26;   // after instances are flattened (~3 GiB of scene)
  uint64_t maxVertices = uint64_t{1} << 27;    // after instances are flattened; indices are 32-bit
  uint64_t maxJsonValues = uint64_t{1} << 24;  // per JSON document: parsed JSON takes ~100 bytes per value
  // A glTF document's parse, estimated before it is built: ~100 bytes per JSON value (tinygltf's DOM) and tinygltf's
  // struct per element of each top-level array (416 bytes an accessor, 456 a node, 2144 a material, ...).
  uint64_t maxParseBytes = uint64_t{1} << 30;
  // Decoded alpha-texture bytes (one per texel) of all the textures one load keeps; more is an error naming the
  // image. Also the bound on the texels of one image decoded on the way (pixels x channels). At most 2^32 - 1.
  uint64_t maxTextureBytes = uint64_t{256} << 20;
  // The cutoff of alphaMode BLEND materials, drawn as MASK (glTF has no cutoff for BLEND). In [0, 1].
  float blendCutoff = 0.5f;
  WarningSink warn;         // empty: one line per warning on stderr
  FileReadSink onFileRead;  // empty: nobody watches
  // glTF animation: the time in seconds at which the animations are evaluated (none: the file's static pose), and
  // which ones ("": every animation; else an animation's index or name).
  std::optional<double> time;
  std::string animation;
};

// `text` for a message: control bytes written as \0, \n, \t or \xNN, since a NUL would cut the message short where
// it is printed as a C string (exception::what) and the others would garble the terminal.
inline std::string visible(std::string_view text) {
  std::string out;
  for (char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if (u >= 0x20 && u != 0x7f) {
      out += c;
      continue;
    }
    static constexpr char kHex[] = "0123456789abcdef";
    out += c == '\0'   ? std::string("\\0")
           : c == '\n' ? std::string("\\n")
           : c == '\t' ? std::string("\\t")
                       : std::string{'\\', 'x', kHex[u >> 4], kHex[u & 15]};
  }
  return out;
}

// Sends `message` to options.warn, or to stderr when no sink is set.
void emitWarning(const LoadOptions& options, const std::string& message);

}  // namespace penumbra
