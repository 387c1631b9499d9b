// Pyramid stage (the default, batched schedule) against the double reference: moment mip chains (1/2/4
// channels, odd, prime, thin and 1x1 sizes; every level keeps the mean) and the min-max depth pyramid with
// background and NaN texels. The batched schedule against the per-level one: pyramid_schedule_test.cpp.
#include "host/stages/pyramid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "host/cl/buffer.h"
#include "tests/reference/pyramid_ref.h"
#include "tests/support/cl_test.h"
#include "tests/support/compare.h"
#include "tests/support/random_images.h"

namespace penumbra {
namespace pyramid_test {
using test::kPoison;
using test::Tolerance;

// Each level is <= 9 fp32 products of the previous one (data in [0, 1]); errors add over <= 8 levels.
constexpr Tolerance kMipTol{2e-6, 1e-6};
// The mean of a level (a double sum of fp32 texels) drifts by the per-level rounding only.
constexpr double kMeanTol = 1e-5;

struct Case {
  uint32_t width, height, channels;
};

std::string caseName(const ::testing::TestParamInfo<Case>& p) {
  return fmt::format("{}x{}_c{}", p.param.width, p.param.height, p.param.channels);
}

class PyramidMips : public test::ClTestWithParam<Case> {};

TEST_P(PyramidMips, MatchesReferenceAndKeepsTheMean) {
  const Case c = GetParam();
  const ImageShape shape{c.width, c.height, c.channels};
  const std::vector<float> base = test::randomUnitImage(shape.count(), c.width * 3 + c.height);
  const PyramidLayout layout = pyramidLayout(c.width, c.height, 1);
  Buffer<float> in(ctx(), std::span<const float>(base)), mips(ctx(), std::max<size_t>(1, layout.texels * c.channels));
  mips.fill(ctx(), kPoison);
  computeMomentMips(ctx(), in, shape, mips);
  const std::vector<float> actual = mips.download(ctx());
  const auto expected = ref::momentMips(std::vector<double>(base.begin(), base.end()), shape);
  ASSERT_EQ(expected.size(), layout.levels.size());
  double baseMean = 0.0;
  for (float v : base) baseMean += v;
  baseMean /= double(base.size());
  for (size_t l = 0; l < expected.size(); ++l) {
    const PyramidLevel& level = layout.levels[l];
    const std::span<const float> got(actual.data() + size_t(level.offset) * c.channels, expected[l].size());
    EXPECT_TRUE(test::allNear(got, std::span<const double>(expected[l]), kMipTol, level.width * c.channels))
        << "level " << l + 1;
    double mean = 0.0;
    for (float v : got) mean += v;
    EXPECT_NEAR(mean / double(got.size()), baseMean, kMeanTol) << "level " << l + 1;
  }
}

// ESM's log-space mips: each level's D has e^(c D) the area average of e^(c D) over the level above, from the double
// reference of the linear mips applied to e^(c (d - 1)) (no overflow, and no underflow in double up to c = 700), at
// the linear limit c = 0, the paper's 80 and 600. fp32 rounds each level's D to ~6e-8 and its taps' c (d - m) to
// ~6e-8 relative; errors add over the levels. Absolute, in normalised depth.
constexpr Tolerance kLogMipTol{2e-6, 0.0};

class PyramidLogMips : public test::ClTest {};

TEST_F(PyramidLogMips, AverageTheExponentials) {
  for (const auto& [width, height] :
       {std::pair<uint32_t, uint32_t>{1, 1}, {97, 61}, {64, 64}, {300, 1}, {1, 300}, {1021, 3}}) {
    const ImageShape shape{width, height, 1};
    const std::vector<float> base = test::randomUnitImage(shape.count(), width * 5 + height);
    const PyramidLayout layout = pyramidLayout(width, height, 1);
    for (float exponent : {0.0f, 80.0f, 600.0f}) {
      Buffer<float> in(ctx(), std::span<const float>(base)), mips(ctx(), std::max<size_t>(1, layout.texels));
      mips.fill(ctx(), kPoison);
      computeLogMomentMips(ctx(), in, shape, mips, exponent);
      const std::vector<float> actual = mips.download(ctx());
      std::vector<double> warped;
      for (float d : base) warped.push_back(exponent == 0.0f ? d : std::exp(exponent * (d - 1.0)));
      const auto levels = ref::momentMips(warped, shape);
      ASSERT_EQ(levels.size(), layout.levels.size());
      for (size_t l = 0; l < levels.size(); ++l) {
        std::vector<double> expected;
        for (double v : levels[l]) expected.push_back(exponent == 0.0f ? v : 1.0 + std::log(v) / exponent);
        const std::span<const float> got(actual.data() + layout.levels[l].offset, expected.size());
        EXPECT_TRUE(test::allNear(got, std::span<const double>(expected), kLogMipTol, layout.levels[l].width))
            << width << "x" << height << " level " << l + 1 << " c " << exponent;
      }
    }
  }
  Buffer<float> two(ctx(), 2), mips(ctx(), 1);
  EXPECT_THROW(computeLogMomentMips(ctx(), two, ImageShape{1, 1, 2}, mips, 80.0f), std::invalid_argument);
}

INSTANTIATE_TEST_SUITE_P(Pyramid, PyramidMips,
                         ::testing::Values(Case{1, 1, 2}, Case{97, 61, 2}, Case{64, 64, 1}, Case{2, 17, 4},
                                           Case{300, 1, 1}, Case{1, 300, 2}, Case{45, 23, 4}, Case{1021, 3, 4}),
                         caseName);

class PyramidMinMax : public test::ClTestWithParam<Case> {};

TEST_P(PyramidMinMax, MatchesReference) {
  const Case c = GetParam();
  const std::vector<float> base =
      test::randomDepthMap(c.width, c.height, c.width + 5 * c.height, c.channels == 0);  // 0 channels: empty map
  const PyramidLayout layout = pyramidLayout(c.width, c.height, 0);
  Buffer<float> in(ctx(), std::span<const float>(base));
  Buffer<cl_float2> out(ctx(), layout.texels);
  out.fill(ctx(), {{kPoison, kPoison}});
  computeMinMaxPyramid(ctx(), in, c.width, c.height, out);
  const std::vector<cl_float2> actual = out.download(ctx());
  const auto expected = ref::minMaxPyramid(base, c.width, c.height);
  ASSERT_EQ(expected.size(), layout.levels.size());
  for (size_t l = 0; l < expected.size(); ++l) {
    size_t mismatches = 0;
    for (size_t i = 0; i < expected[l].size(); ++i) {
      const cl_float2 got = actual[layout.levels[l].offset + i];
      mismatches += got.s[0] != expected[l][i].first || got.s[1] != expected[l][i].second;
    }
    EXPECT_EQ(mismatches, 0u) << "level " << l << " (min and max are exact)";
  }
}

// Levels 1.. alone (computeMinMaxLevels), background and NaN the farthest depth: the reference's pyramid of the map
// with them replaced by a finite sentinel above every depth, the sentinel read back as +INFINITY. Exact, and the
// returned top is the last level.
TEST_P(PyramidMinMax, LevelsAboveTheMapMatchTheReference) {
  const Case c = GetParam();
  const std::vector<float> base =
      test::randomDepthMap(c.width, c.height, c.width + 5 * c.height, c.channels == 0);  // 0 channels: empty map
  constexpr float kFar = 3e38f;
  std::vector<float> far = base;
  for (float& z : far) z = std::isfinite(z) ? z : kFar;
  const auto expected = ref::minMaxPyramid(far, c.width, c.height);
  auto unsentinel = [&](float v) { return v == kFar ? INFINITY : v; };
  const PyramidLayout layout = pyramidLayout(c.width, c.height, 1);
  ASSERT_EQ(expected.size(), layout.levels.size() + 1);
  Buffer<float> in(ctx(), std::span<const float>(base));
  Buffer<cl_float2> out(ctx(), std::max<size_t>(layout.texels, 1));
  out.fill(ctx(), {{kPoison, kPoison}});
  const cl_float2 top = computeMinMaxLevels(ctx(), in, c.width, c.height, out);
  const std::vector<cl_float2> actual = out.download(ctx());
  for (size_t l = 1; l < expected.size(); ++l) {
    size_t mismatches = 0;
    for (size_t i = 0; i < expected[l].size(); ++i) {
      const cl_float2 got = actual[layout.levels[l - 1].offset + i];
      mismatches += got.s[0] != unsentinel(expected[l][i].first) || got.s[1] != unsentinel(expected[l][i].second);
    }
    EXPECT_EQ(mismatches, 0u) << "level " << l << " (min and max are exact)";
  }
  EXPECT_EQ(top.s[0], unsentinel(expected.back()[0].first));
  EXPECT_EQ(top.s[1], unsentinel(expected.back()[0].second));
  EXPECT_THROW(computeMinMaxLevels(ctx(), in, c.width, c.height, out, {PyramidSchedule::PerLevel}),
               std::invalid_argument);
}

// channels == 0 marks an all-background map.
INSTANTIATE_TEST_SUITE_P(Pyramid, PyramidMinMax,
                         ::testing::Values(Case{1, 1, 1}, Case{97, 61, 1}, Case{128, 64, 1}, Case{3, 41, 1},
                                           Case{1021, 3, 1}, Case{13, 9, 0}),
                         caseName);

TEST(PyramidLayoutTest, LevelsAndOffsets) {
  const PyramidLayout full = pyramidLayout(97, 61, 0);
  ASSERT_EQ(full.levels.size(), 7u);  // 97x61 48x30 24x15 12x7 6x3 3x1 1x1
  EXPECT_EQ(full.levels[5].width, 3u);
  EXPECT_EQ(full.levels[5].height, 1u);
  EXPECT_EQ(full.levels[1].offset, 97u * 61u);
  EXPECT_EQ(full.texels, 97u * 61 + 48 * 30 + 24 * 15 + 12 * 7 + 6 * 3 + 3 + 1);
  const PyramidLayout mips = pyramidLayout(97, 61, 1);
  EXPECT_EQ(mips.levels.size(), 6u);
  EXPECT_EQ(mips.levels[0].offset, 0u);
  EXPECT_TRUE(pyramidLayout(1, 1, 1).levels.empty());
  EXPECT_EQ(pyramidLayout(4096, 4096, 0).levels.size(), 13u);
}

}  // namespace pyramid_test
}  // namespace penumbra
