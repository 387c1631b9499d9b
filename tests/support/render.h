// One frame through the whole pipeline for the technique tests: a fresh Renderer, the named technique at its
// defaults with `values` set on top (each validated like a CLI option).
#pragma once

#include <gtest/gtest.h>

#include <cmath>
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

// No NaN in any channel and every visibility.Y value within [0, 1]; a failure names `what`, the channel and the
// first offending value. Use as ASSERT_TRUE(test::saneImage(...)) or EXPECT_TRUE.
inline ::testing::AssertionResult saneImage(const Image& image, const std::string& what) {
  for (const ImageChannel& channel : image.channels())
    for (float v : channel.data)
      if (std::isnan(v)) return ::testing::AssertionFailure() << what << ": NaN in " << channel.name;
  for (float v : image.require("visibility.Y").data)
    if (!(v >= 0.0f && v <= 1.0f)) return ::testing::AssertionFailure() << what << ": visibility " << v;
  return ::testing::AssertionSuccess();
}

}  // namespace penumbra::test
