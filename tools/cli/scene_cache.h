// The scenes a batch run renders, loaded once and kept (the last few, least recently used first out) with their
// Renderer, so consecutive jobs on one scene reuse its uploaded triangles, G-buffer and technique buffers, and each
// scene's content digest (for job ids) computed once per scene spec.
#pragma once

#include <list>
#include <map>
#include <memory>
#include <string>

#include "host/cl/context.h"
#include "host/pipeline/renderer.h"
#include "tools/cli/manifest.h"

namespace penumbra::cli {

class SceneCache {
 public:
  explicit SceneCache(size_t capacity = 2) : capacity_(capacity) {}

  struct Entry {
    std::string key;  // sceneProvenance and the blend cutoff: what the load depends on
    Scene scene;
    std::unique_ptr<Renderer> renderer;  // made on first use; declared after scene: destroyed first
  };

  // The scene of `view` (loaded now, or kept from before), most recently used from now on.
  Entry& get(const ViewOptions& view);
  // Its Renderer on `ctx`, made the first time.
  Renderer& renderer(Entry& entry, Context& ctx);
  // The scene's digest (manifest.h sceneDigest): a built-in scene's spec, else from the first load of its spec.
  const std::string& digest(const ViewOptions& view);

 private:
  size_t capacity_;
  std::list<Entry> entries_;                    // most recent first
  std::map<std::string, std::string> digests_;  // scene spec -> digest
};

// The key of the load `view` asks for.
std::string sceneKey(const ViewOptions& view);

}  // namespace penumbra::cli
