// A short list searched linearly: a batch keeps a handful of scenes at most (a shard's jobs are ordered by scene).
#include "tools/cli/scene_cache.h"

#include <fmt/format.h>

namespace penumbra::cli {

std::string sceneKey(const ViewOptions& view) {
  return fmt::format("{} blend-cutoff={}", sceneProvenance(view), view.blendCutoff);
}

SceneCache::Entry& SceneCache::get(const ViewOptions& view) {
  const std::string key = sceneKey(view);
  for (auto it = entries_.begin(); it != entries_.end(); ++it)
    if (it->key == key) {
      entries_.splice(entries_.begin(), entries_, it);
      return entries_.front();
    }
  HashedScene loaded = loadHashedScene(view);
  digests_.emplace(view.scene, loaded.digest);
  while (entries_.size() >= capacity_ && !entries_.empty()) entries_.pop_back();
  entries_.push_front({key, std::move(loaded.scene), nullptr});
  return entries_.front();
}

Renderer& SceneCache::renderer(Entry& entry, Context& ctx) {
  if (!entry.renderer) entry.renderer = std::make_unique<Renderer>(ctx, entry.scene);
  return *entry.renderer;
}

const std::string& SceneCache::digest(const ViewOptions& view) {
  if (auto it = digests_.find(view.scene); it != digests_.end()) return it->second;
  if (view.scene.rfind("builtin:", 0) == 0) return digests_.emplace(view.scene, view.scene).first->second;
  get(view);
  return digests_.at(view.scene);
}

}  // namespace penumbra::cli
