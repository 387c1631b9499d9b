// One frame through the whole pipeline for the technique tests: renderWith (a fresh Renderer, the named technique at
// its defaults with `values` set on top) lives with the analytic scenes, which `penumbra selftest` shares; here the
// GoogleTest side of a frame's sanity.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "tools/selftest/reference/analytic_scenes.h"

namespace penumbra::test {

// No NaN in any channel and every visibility.Y value within [0, 1] (imageDefect); a failure names `what`, the channel
// and the first offending value. Use as ASSERT_TRUE(test::saneImage(...)) or EXPECT_TRUE.
inline ::testing::AssertionResult saneImage(const Image& image, const std::string& what) {
  const std::string defect = imageDefect(image);
  if (defect.empty()) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << what << ": " << defect;
}

}  // namespace penumbra::test
