// One frame through the whole pipeline for the technique tests: a fresh Renderer, the named technique at its
// defaults with `values` set on top (each validated like a CLI option).
#pragma once

#include <map>
#include <string>

#include "host/pipeline/renderer.h"
#include "host/techniques/registry.h"

namespace penumbra::test {

using Values = std::map<std::string, std::string>;

inline RenderResult renderWith(Context& ctx, const Scene& scene, const Camera& camera, const Light& light,
                               const std::string& technique, const Values& values = {}) {
  const TechniqueInfo& info = findTechnique(technique);
  Params params(info.params);
  for (const auto& [name, value] : values) params.set(name, value);
  Renderer renderer(ctx, scene);
  return renderer.render(camera, light, info, params);
}

}  // namespace penumbra::test
