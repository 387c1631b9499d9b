// Error metrics (host/eval/metrics.h) on hand-computed cases: every statistic on a five-pixel example with
// binary-exact values, the nearest-rank percentile, coverage masks, NaN and infinity rules, empty coverage, the
// threshold check and the size and channel errors of compareImages().
#include "host/eval/metrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace penumbra {
namespace metrics_test {

constexpr float kNan = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

// e = ours - ref = {0, 0.125, 1, -0.75, 0}: one leaking pixel (ref 0, ours 1), one false shadow (ref 1, ours 0.25).
const std::vector<float> kOurs = {0.0f, 0.5f, 1.0f, 0.25f, 0.75f};
const std::vector<float> kRef = {0.0f, 0.375f, 0.0f, 1.0f, 0.75f};

TEST(Metrics, HandComputedFivePixels) {
  const ErrorMetrics m = computeErrorMetrics(kOurs, kRef);
  EXPECT_EQ(m.pixels, 5u);
  EXPECT_EQ(m.nonFinite, 0u);
  EXPECT_DOUBLE_EQ(m.mae, 1.875 / 5);
  EXPECT_DOUBLE_EQ(m.rmse, std::sqrt((0.125 * 0.125 + 1.0 + 0.75 * 0.75) / 5));
  EXPECT_DOUBLE_EQ(m.meanSigned, 0.375 / 5);
  EXPECT_DOUBLE_EQ(m.p95, 1.0);  // ceil(0.95 * 5) = 5th smallest
  EXPECT_DOUBLE_EQ(m.maxAbs, 1.0);
  EXPECT_DOUBLE_EQ(m.off, 3.0 / 5);  // 0.125, 1, 0.75 exceed 0.1
  EXPECT_DOUBLE_EQ(m.leak, 1.0 / 5);
  EXPECT_DOUBLE_EQ(m.falseShadow, 1.0 / 5);
  EXPECT_EQ(m.umbraPixels, 2u);             // reference 0 twice
  EXPECT_DOUBLE_EQ(m.umbraLight, 1.0 / 2);  // of those, ours 1 exceeds 0.1
}

// Light in the umbra counts moderate errors `leak` misses (ours 0.3 where the reference is 0), only over the umbra.
TEST(Metrics, UmbraLightIsAShareOfTheUmbra) {
  const std::vector<float> ref = {0.0f, 0.01f, 0.019f, 0.03f, 0.5f, 1.0f};
  const std::vector<float> ours = {0.3f, 0.09f, 0.11f, 0.3f, 0.9f, 1.0f};
  const ErrorMetrics m = computeErrorMetrics(ours, ref);
  EXPECT_EQ(m.umbraPixels, 3u);             // below 0.02 only
  EXPECT_DOUBLE_EQ(m.umbraLight, 2.0 / 3);  // 0.3 and 0.11 exceed 0.1, 0.09 does not
  EXPECT_DOUBLE_EQ(m.leak, 0.0);            // no pixel brighter than 0.5 where the reference is below 0.05
  MetricThresholds limits;
  limits.umbraLight = 0.5;
  const std::vector<std::string> failed = exceededThresholds(m, limits);
  ASSERT_EQ(failed.size(), 1u);
  EXPECT_EQ(failed[0].rfind("umbra-light 0.666667 > 0.5", 0), 0u) << failed[0];
  const ErrorMetrics lit = computeErrorMetrics(std::vector<float>{1.0f}, std::vector<float>{1.0f});
  EXPECT_EQ(lit.umbraPixels, 0u);
  EXPECT_EQ(lit.umbraLight, 0.0);  // no umbra: nothing let in
}

// The penumbra MAE is over the pixels whose reference lies strictly between 0 and 1, where soft shadows differ; the lit
// and umbra pixels (reference exactly 1 or 0) count in `mae` only, and the coverage still applies.
TEST(Metrics, PenumbraMaeIsOverThePenumbraPixelsOnly) {
  const std::vector<float> ref = {0.0f, 1.0f, 0.25f, 0.5f, 0.999f, 0.75f};
  const std::vector<float> ours = {0.5f, 0.5f, 0.5f, 0.5f, 1.0f, 0.0f};
  const std::vector<float> coverage = {1, 1, 1, 1, 1, 0};
  const ErrorMetrics m = computeErrorMetrics(ours, ref, coverage);
  EXPECT_EQ(m.penumbraPixels, 3u);                                 // 0.25, 0.5, 0.999 (0.75 is not covered)
  EXPECT_NEAR(m.penumbraMae, (0.25 + 0.0 + 0.001) / 3.0, 1e-7);   // float 0.999's error, within its rounding
  EXPECT_DOUBLE_EQ(m.mae, (0.5 + 0.5 + 0.25 + 0.0 + (1.0 - double(0.999f))) / 5.0);
  MetricThresholds limits;
  limits.penumbraMae = 0.05;
  const std::vector<std::string> failed = exceededThresholds(m, limits);
  ASSERT_EQ(failed.size(), 1u);
  EXPECT_EQ(failed[0].rfind("penumbra-mae 0.0836", 0), 0u) << failed[0];
  const ErrorMetrics hard = computeErrorMetrics(std::vector<float>{1.0f, 0.0f}, std::vector<float>{0.0f, 1.0f});
  EXPECT_EQ(hard.penumbraPixels, 0u);
  EXPECT_EQ(hard.penumbraMae, 0.0);  // no penumbra: nothing to get wrong there
}

TEST(Metrics, PercentileIsNearestRank) {
  std::vector<float> ours(100), ref(100, 0.0f);
  for (int i = 0; i < 100; ++i) ours[i] = static_cast<float>(100 - i) / 128.0f;  // |e| = 1/128 .. 100/128, shuffled
  EXPECT_DOUBLE_EQ(computeErrorMetrics(ours, ref).p95, 95.0 / 128);
  ours.resize(20), ref.resize(20);  // 20 values: ceil(19) = the 19th smallest
  for (int i = 0; i < 20; ++i) ours[i] = static_cast<float>(i + 1) / 32.0f;
  EXPECT_DOUBLE_EQ(computeErrorMetrics(ours, ref).p95, 19.0 / 32);
  EXPECT_DOUBLE_EQ(computeErrorMetrics(std::vector<float>{0.25f}, std::vector<float>{0.0f}).p95, 0.25);
}

TEST(Metrics, CoverageSelectsPixels) {
  const std::vector<float> coverage = {1.0f, 1.0f, 0.0f, 0.0f, 1.0f};  // drops the leak and the false shadow
  const ErrorMetrics m = computeErrorMetrics(kOurs, kRef, coverage);
  EXPECT_EQ(m.pixels, 3u);
  EXPECT_DOUBLE_EQ(m.mae, 0.125 / 3);
  EXPECT_DOUBLE_EQ(m.leak, 0.0);
  EXPECT_DOUBLE_EQ(m.falseShadow, 0.0);
  const std::vector<float> error = signedError(kOurs, kRef, coverage);
  EXPECT_EQ(error, (std::vector<float>{0.0f, 0.125f, 0.0f, 0.0f, 0.0f}));
}

TEST(Metrics, NonFiniteCoveredPixelsAreCountedLeftOutAndFail) {
  const std::vector<float> ours = {kNan, 0.5f, 1.0f, kNan};
  const std::vector<float> ref = {0.0f, kInf, 1.0f, 0.5f};
  const std::vector<float> coverage = {1.0f, 1.0f, 1.0f, 0.0f};  // the last NaN is background: ignored
  const ErrorMetrics m = computeErrorMetrics(ours, ref, coverage);
  EXPECT_EQ(m.pixels, 1u);
  EXPECT_EQ(m.nonFinite, 2u);
  EXPECT_DOUBLE_EQ(m.mae, 0.0);
  const std::vector<std::string> failed = exceededThresholds(m, {});
  ASSERT_EQ(failed.size(), 1u) << "a NaN pixel fails even without limits";
  EXPECT_NE(failed[0].find("NaN"), std::string::npos);
  EXPECT_TRUE(std::isnan(signedError(ours, ref, coverage)[0]));
}

TEST(Metrics, EmptyCoverageGivesZerosAndPasses) {
  const std::vector<float> none(5, 0.0f);
  const ErrorMetrics m = computeErrorMetrics(kOurs, kRef, none);
  EXPECT_EQ(m.pixels, 0u);
  EXPECT_EQ(m.mae, 0.0);
  EXPECT_EQ(m.p95, 0.0);
  EXPECT_EQ(m.leak, 0.0);
  MetricThresholds zero;
  zero.mae = zero.rmse = zero.p95 = zero.off = zero.leak = zero.falseShadow = zero.bias = 0.0;
  EXPECT_TRUE(exceededThresholds(m, zero).empty());
  EXPECT_EQ(computeErrorMetrics(std::vector<float>{}, std::vector<float>{}).pixels, 0u);
}

TEST(Metrics, ThresholdsAreInclusiveAndBiasIsAbsolute) {
  const ErrorMetrics m = computeErrorMetrics(kOurs, kRef);
  MetricThresholds limits;
  limits.mae = m.mae;  // equal: within
  limits.bias = 0.075;
  EXPECT_TRUE(exceededThresholds(m, limits).empty());
  limits.leak = 0.1;
  limits.bias = 0.07;
  const std::vector<std::string> failed = exceededThresholds(m, limits);
  ASSERT_EQ(failed.size(), 2u);
  EXPECT_EQ(failed[0].rfind("leak", 0), 0u) << failed[0];
  EXPECT_EQ(failed[1].rfind("bias", 0), 0u) << failed[1];
  // Roles swapped: mean signed -0.075 (|bias| still over 0.07); the leak becomes a false shadow (no limit).
  const std::vector<std::string> darker = exceededThresholds(computeErrorMetrics(kRef, kOurs), limits);
  ASSERT_EQ(darker.size(), 1u);
  EXPECT_EQ(darker[0].rfind("bias", 0), 0u) << darker[0];
}

TEST(Metrics, SizeMismatchThrows) {
  EXPECT_THROW(computeErrorMetrics(std::vector<float>(4), std::vector<float>(5)), std::invalid_argument);
  EXPECT_THROW(computeErrorMetrics(kOurs, kRef, std::vector<float>(4)), std::invalid_argument);
  EXPECT_THROW(signedError(std::vector<float>(4), std::vector<float>(5)), std::invalid_argument);
}

Image image(int width, int height, const std::string& source, float value) {
  Image im(width, height, source);
  im.addFilled("visibility.Y", value);
  return im;
}

TEST(Metrics, CompareImagesChecksSizeAndChannelAndUsesCoverage) {
  try {
    compareImages(image(4, 3, "ours.exr", 0.0f), image(3, 4, "ref.exr", 0.0f));
    FAIL() << "expected a size mismatch";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("ours.exr is 4x3 but ref.exr is 3x4"), std::string::npos) << e.what();
  }
  EXPECT_THROW(compareImages(image(2, 2, "a", 0.0f), image(2, 2, "b", 0.0f), {"stderr.Y", "A"}), std::runtime_error);

  Image ours = image(2, 2, "ours", 0.5f), ref = image(2, 2, "ref", 0.25f);
  EXPECT_EQ(compareImages(ours, ref).pixels, 4u);  // no coverage channel anywhere: every pixel
  ours.add("A", {1.0f, 0.0f, 0.0f, 0.0f});         // only ours has one: it is used
  EXPECT_EQ(compareImages(ours, ref).pixels, 1u);
  ref.add("A", {1.0f, 1.0f, 0.0f, 0.0f});  // the reference's wins
  const ErrorMetrics m = compareImages(ours, ref);
  EXPECT_EQ(m.pixels, 2u);
  EXPECT_DOUBLE_EQ(m.meanSigned, 0.25);
}

}  // namespace metrics_test
}  // namespace penumbra
