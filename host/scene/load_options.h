// What every scene loader shares: the error type for bad input (messages name the file and the element)
// and the limits and warning sink a caller passes in.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>

namespace penumbra {

// Bad or unsupported input: "scene.gltf: accessor 12: index 7071 out of range (vertex count 512)".
class SceneError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

using WarningSink = std::function<void(const std::string&)>;

struct LoadOptions {
  uint64_t maxFileBytes = uint64_t{1} << 30;   // per file read (.gltf, .glb, .bin, .json)
  uint64_t maxTotalBytes = uint64_t{4} << 30;  // all files one load reads, together
  uint64_t maxTriangles = uint64_t{1} << 26;   // after instances are flattened (~3 GiB of scene)
  uint64_t maxVertices = uint64_t{1} << 27;    // after instances are flattened; indices are 32-bit
  uint64_t maxJsonValues = uint64_t{1} << 24;  // per JSON document: parsed JSON takes ~100 bytes per value
  WarningSink warn;                            // empty: one line per warning on stderr
  // glTF animation: the time in seconds at which the animations are evaluated (none: the file's static pose), and
  // which ones ("": every animation; else an animation's index or name).
  std::optional<double> time;
  std::string animation;
};

// Sends `message` to options.warn, or to stderr when no sink is set.
void emitWarning(const LoadOptions& options, const std::string& message);

}  // namespace penumbra
