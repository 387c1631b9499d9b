// The shimmer metric (tools/eval/shimmer.h) on hand-computed frames: only stable, covered pixels count; NaN counts as
// a full change; sizes must agree; pairs combine pixel-weighted.
#include "tools/eval/shimmer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace penumbra {
namespace shimmer_test {

TEST(Shimmer, CountsOnlyPixelsWhoseReferenceIsStable) {
  // Pixel 0: reference stable, ours changes 0.5. Pixel 1: the reference's edge moves (1 -> 0): not counted.
  // Pixel 2: stable, ours still. Pixel 3: stable within kStableReference (0.01), ours changes 0.05.
  const std::vector<float> a{0.2f, 1.0f, 1.0f, 0.5f}, b{0.7f, 0.0f, 1.0f, 0.55f};
  const std::vector<float> ra{0.0f, 1.0f, 1.0f, 0.50f}, rb{0.0f, 0.0f, 1.0f, 0.51f};
  const ShimmerMetrics m = frameShimmer(a, b, ra, rb);
  EXPECT_EQ(m.pixels, 3u);
  EXPECT_NEAR(m.mean, (0.5 + 0.0 + 0.05) / 3, 1e-6);
  EXPECT_NEAR(m.fraction, 1.0 / 3, 1e-12);  // only pixel 0 exceeds kShimmerStep
  EXPECT_NEAR(m.maxAbs, 0.5, 1e-6);
}

TEST(Shimmer, CoverageOfBothFramesAndNaN) {
  const std::vector<float> a{0.0f, 0.0f, NAN}, b{1.0f, 1.0f, 0.0f}, r{1.0f, 1.0f, 1.0f};
  const std::vector<float> ca{1.0f, 0.0f, 1.0f}, cb{1.0f, 1.0f, 1.0f};
  const ShimmerMetrics m = frameShimmer(a, b, r, r, ca, cb);  // pixel 1 is not seen in frame a
  EXPECT_EQ(m.pixels, 2u);
  EXPECT_DOUBLE_EQ(m.mean, 1.0);
  EXPECT_DOUBLE_EQ(m.fraction, 1.0);
}

TEST(Shimmer, StillFramesAndEmptyInput) {
  const std::vector<float> v{0.25f, 0.75f};
  const ShimmerMetrics still = frameShimmer(v, v, v, v);
  EXPECT_EQ(still.pixels, 2u);
  EXPECT_EQ(still.mean, 0.0);
  EXPECT_EQ(still.maxAbs, 0.0);
  const ShimmerMetrics none = frameShimmer({}, {}, {}, {});
  EXPECT_EQ(none.pixels, 0u);
  EXPECT_EQ(none.mean, 0.0);
}

TEST(Shimmer, RefusesMismatchedSizes) {
  const std::vector<float> two{0, 0}, three{0, 0, 0};
  EXPECT_THROW(frameShimmer(two, three, two, two), std::invalid_argument);
  EXPECT_THROW(frameShimmer(two, two, two, two, three, {}), std::invalid_argument);
}

TEST(Shimmer, CombinesPairsByPixelCount) {
  ShimmerMetrics a, b;
  a.pixels = 1, a.mean = 1.0, a.fraction = 1.0, a.maxAbs = 1.0;
  b.pixels = 3, b.mean = 0.0, b.fraction = 0.0, b.maxAbs = 0.0;
  const ShimmerMetrics all = combineShimmer({a, b});
  EXPECT_EQ(all.pixels, 4u);
  EXPECT_DOUBLE_EQ(all.mean, 0.25);
  EXPECT_DOUBLE_EQ(all.fraction, 0.25);
  EXPECT_DOUBLE_EQ(all.maxAbs, 1.0);
  EXPECT_EQ(combineShimmer({}).pixels, 0u);
}

}  // namespace shimmer_test
}  // namespace penumbra
