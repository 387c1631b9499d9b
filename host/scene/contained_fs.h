// File access for scene loading: URIs inside a glTF model (buffers, images) must stay inside the model's
// folder; a scene file's model paths are the user's own (absolute, or relative to the scene file, ".." allowed);
// every read is a regular file under per-file and per-load size caps.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "host/scene/load_options.h"

namespace penumbra::detail {

// The canonical path of `relative` under `root` (a canonical directory). Throws SceneError (message
// without a file prefix) for an empty path, a URI scheme, an absolute path, a ".." component, a missing
// file, a symlink that leads outside `root`, or something that is not a regular file.
std::filesystem::path resolveInside(const std::filesystem::path& root, std::string_view relative);

// The canonical path of a model a scene file names: `path` absolute, or relative to `folder` (the scene file's
// canonical folder; ".." allowed). Throws SceneError (message without a file prefix) for an empty path, a URI
// scheme, a missing file (naming where it was looked for) or something that is not a regular file.
std::filesystem::path resolveSceneModel(const std::filesystem::path& folder, std::string_view path);

// The canonical path of a file the user named directly (no containment); throws SceneError naming the
// path when it does not exist or is not a regular file.
std::filesystem::path resolveUserFile(const std::string& path);

// Reads whole files for one load, enforcing LoadOptions::maxFileBytes per file and maxTotalBytes overall, and keeps
// the load's budget of decoded alpha-texture bytes (LoadOptions::maxTextureBytes).
class FileReader {
 public:
  explicit FileReader(const LoadOptions& options)
      : maxFileBytes_(options.maxFileBytes),
        remainingBytes_(options.maxTotalBytes),
        maxTextureBytes_(options.maxTextureBytes),
        remainingTextureBytes_(options.maxTextureBytes),
        onRead_(options.onFileRead) {}
  // Throws SceneError (message without a file prefix) when the file is too big or cannot be read.
  std::vector<unsigned char> read(const std::filesystem::path& path);

  // Takes `bytes` of decoded texels from the budget; throws SceneError (message without a file prefix, naming
  // `what`) when they do not fit.
  void claimTextureBytes(uint64_t bytes, const std::string& what);
  uint64_t maxTextureBytes() const { return maxTextureBytes_; }

 private:
  uint64_t maxFileBytes_;
  uint64_t remainingBytes_;
  uint64_t maxTextureBytes_;
  uint64_t remainingTextureBytes_;
  FileReadSink onRead_;
};

}  // namespace penumbra::detail
