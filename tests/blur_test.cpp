// Blur stage against the double reference: Gaussian and box, direct and running sums, 1/2/4 channels,
// 1x1, prime and thin sizes, radii larger than the image, per-split scale, constant and huge-range input; the
// direct plan's two layouts (tiles, runs) against each other.
#include "host/stages/blur.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "host/cl/buffer.h"
#include "tests/support/cl_test.h"
#include "tests/support/compare.h"
#include "tools/selftest/blur_checks.h"
#include "tools/selftest/reference/blur_ref.h"
#include "tools/selftest/reference/cases.h"
#include "tools/selftest/reference/inputs.h"
#include "tools/selftest/reference/tolerance.h"
#include "tools/selftest/stage_checks.h"

namespace penumbra {
namespace blur_test {
using test::kPoison;

using ref::kBlurBoxesVsGaussianTol;
using ref::kBlurLayoutTol;
using ref::kBlurRunningTol;

using Input = ref::BlurInput;

using Case = ref::BlurCase;

std::vector<float> run(test::ClTest& fixture, Context& ctx, const std::vector<double>& image, const ImageShape& shape,
                       const BlurConfig& config) {
  (void)fixture;
  const std::vector<float> input(image.begin(), image.end());
  Buffer<float> in(ctx, std::span<const float>(input)), out(ctx, shape.count()), scratch(ctx, shape.count());
  out.fill(ctx, kPoison);
  scratch.fill(ctx, kPoison);
  blur(ctx, in, out, scratch, shape, config);
  return out.download(ctx);
}

class BlurTest : public test::ClTestWithParam<Case> {};

// The check is `penumbra selftest`'s (tools/selftest/stage_checks.h), in the device's own layout.
TEST_P(BlurTest, MatchesReference) {
  EXPECT_TRUE(test::passes(selftest::checkBlur(ctx(), GetParam(), BlurLayout::Auto).comparison));
}

using ref::boxBlur;
using ref::gaussianBlur;

INSTANTIATE_TEST_SUITE_P(Blur, BlurTest, ::testing::ValuesIn(ref::blurCases()),
                         [](const ::testing::TestParamInfo<Case>& p) { return p.param.name; });

TEST(BlurPlan, BoxesMatchGaussianVariance) {
  for (float sigma : {11.0f, 14.0f, 25.0f, 80.0f}) {
    const BlurPlan plan = planBlur(gaussianBlur(sigma));
    ASSERT_FALSE(plan.direct);
    double variance = 0.0;
    for (int r : plan.boxRadii) variance += ((2.0 * r + 1) * (2.0 * r + 1) - 1.0) / 12.0;
    // Odd widths move the variance in steps of ~2 * width / 12: within one box width of sigma^2.
    EXPECT_NEAR(variance, double(sigma) * sigma, 2.0 * sigma) << "sigma " << sigma;
  }
  EXPECT_TRUE(planBlur(gaussianBlur(10.0f)).direct);
  EXPECT_EQ(planBlur(gaussianBlur(2.0f, 1.5f)).radius, 9);
  EXPECT_EQ(planBlur(boxBlur(4)).weights.size(), 9u);
  EXPECT_THROW(planBlur(gaussianBlur(-1.0f)), std::invalid_argument);
  EXPECT_THROW(planBlur(boxBlur(200, BlurMethod::Direct)), std::invalid_argument);
  EXPECT_THROW(planBlur(gaussianBlur(1.0f, std::nanf(""))), std::invalid_argument);
}

class BlurKernels : public test::ClTest {};

TEST_F(BlurKernels, BoxesApproximateTheGaussian) {
  // Away from the borders only: clamping after every box is not clamping the Gaussian once.
  constexpr int kSigma = 12, kMargin = 4 * kSigma;
  const ImageShape shape{2 * kMargin + 37, 2 * kMargin + 23, 1};
  const std::vector<double> image = ref::blurImage(shape, Input::Random, 5);
  const std::vector<float> actual = run(*this, ctx(), image, shape, gaussianBlur(float(kSigma)));
  const std::vector<double> exact = ref::convolveSeparable(image, shape, ref::gaussianTaps(kSigma));
  std::vector<float> inner;
  std::vector<double> innerExact;
  for (uint32_t y = kMargin; y + kMargin < shape.height; ++y)
    for (uint32_t x = kMargin; x + kMargin < shape.width; ++x) {
      inner.push_back(actual[y * shape.width + x]);
      innerExact.push_back(exact[y * shape.width + x]);
    }
  EXPECT_TRUE(
      test::allNear(std::span<const float>(inner), std::span<const double>(innerExact), kBlurBoxesVsGaussianTol));
}

TEST_F(BlurKernels, InPlaceMatchesOutOfPlace) {
  const ImageShape shape{45, 29, 2};
  const std::vector<double> image = ref::blurImage(shape, Input::Random, 9);
  const std::vector<float> input(image.begin(), image.end());
  for (const BlurConfig& config : {gaussianBlur(3.0f), gaussianBlur(15.0f)}) {
    Buffer<float> buffer(ctx(), std::span<const float>(input)), scratch(ctx(), shape.count());
    blur(ctx(), buffer, buffer, scratch, shape, config);
    const std::vector<float> inPlace = buffer.download(ctx());
    const std::vector<float> outOfPlace = run(*this, ctx(), image, shape, config);
    EXPECT_EQ(inPlace, outOfPlace);
  }
}

// The moments stage fused into the row pass equals moments then blur bit for bit, for every single-plane
// encoding, direct and running-sum plans, on depth with background (+inf), NaN and out-of-range texels.
TEST_F(BlurKernels, FusedMomentsEqualMomentsThenBlur) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> depthDist(1.5f, 9.5f);  // beyond [2, 9] on both sides: clamped
  for (const auto& [width, height] : {std::pair<uint32_t, uint32_t>{67, 41}, {1, 1}, {130, 3}}) {
    std::vector<float> depth(size_t(width) * height);
    for (size_t i = 0; i < depth.size(); ++i)
      depth[i] = i % 11 == 3 ? INFINITY : i % 17 == 5 ? std::nanf("") : depthDist(rng);
    const Buffer<float> depthBuffer(ctx(), std::span<const float>(depth));
    for (MomentKind kind : {MomentKind::Vsm, MomentKind::Evsm2, MomentKind::Evsm4, MomentKind::Msm})
      for (BlurConfig config : {gaussianBlur(2.0f), boxBlur(3), gaussianBlur(15.0f)})
        for (BlurLayout layout : {BlurLayout::Tiles, BlurLayout::Runs}) {
          config.layout = layout;
          MomentsConfig moments;
          moments.kind = kind;
          moments.depthNear = 2.0f, moments.depthFar = 9.0f;
          const ImageShape shape{width, height, momentChannels(kind)};
          Buffer<float> separate(ctx(), shape.count()), fused(ctx(), shape.count()), scratch(ctx(), shape.count());
          separate.fill(ctx(), kPoison);
          fused.fill(ctx(), kPoison);
          scratch.fill(ctx(), kPoison);
          computeMoments(ctx(), depthBuffer, width, height, moments, separate);
          blur(ctx(), separate, separate, scratch, shape, config);
          scratch.fill(ctx(), kPoison);
          blurMoments(ctx(), depthBuffer, moments, fused, scratch, width, height, config);
          EXPECT_EQ(fused.download(ctx()), separate.download(ctx()))
              << width << "x" << height << " kind " << static_cast<int>(kind) << " radius " << planBlur(config).radius
              << " layout " << static_cast<int>(layout);
        }
  }
  MomentsConfig layered;
  layered.kind = MomentKind::Lvsm;
  layered.layers = {{0.0f, 1.0f}};
  Buffer<float> depth(ctx(), 4), out(ctx(), 8), scratch(ctx(), 8);
  EXPECT_THROW(blurMoments(ctx(), depth, layered, out, scratch, 2, 2, gaussianBlur(1.0f)), std::invalid_argument);
}

// ESM's filtered depth against the double reference in log space and linearly: the cases, the run and the margin
// (ref::kLogBlurTol) are tools/selftest/blur_checks.h's, which `penumbra selftest` runs too; the log-space kernels
// refuse running-sum plans.
TEST_F(BlurKernels, EsmBlursInLogSpace) {
  for (const selftest::EsmBlurCase& c : selftest::esmBlurCases()) {
    const ref::Comparison cmp = selftest::esmBlur(ctx(), c);
    EXPECT_TRUE(cmp.pass()) << c.name() << ": " << cmp.mismatches << " of " << cmp.count << " off" << cmp.report;
  }
  MomentsConfig esm;
  esm.kind = MomentKind::Esm;
  esm.esmExponent = 200.0f;
  Buffer<float> depth(ctx(), 4), out(ctx(), 4), scratch(ctx(), 4);
  EXPECT_THROW(blurMoments(ctx(), depth, esm, out, scratch, 2, 2, gaussianBlur(15.0f)), std::invalid_argument);
}

// Tiles and runs on the same input: odd, prime and thin sizes (rows shorter than a run, widths that are not a
// multiple of it, radii beyond the image), 1, 2 and 4 channels, radius 0 to 100.
TEST_F(BlurKernels, LayoutsAgree) {
  const std::pair<uint32_t, uint32_t> sizes[] = {{1, 1}, {97, 61}, {5, 131}, {523, 3}, {37, 29}};
  const BlurConfig configs[] = {gaussianBlur(0.0f),
                                gaussianBlur(1.0f),
                                boxBlur(1),
                                gaussianBlur(2.0f),
                                boxBlur(13),
                                gaussianBlur(10.7f),
                                boxBlur(100, BlurMethod::Direct)};
  for (const auto& [width, height] : sizes)
    for (uint32_t channels : {1u, 2u, 4u})
      for (BlurConfig config : configs) {
        const ImageShape shape{width, height, channels};
        const std::vector<double> image = ref::blurImage(shape, Input::Random, width + height + channels);
        config.method = BlurMethod::Direct;  // the direct layouts (running-sum plans: RunsLayoutBoxesMatchRunningSums)
        config.layout = BlurLayout::Tiles;
        const std::vector<float> tiles = run(*this, ctx(), image, shape, config);
        config.layout = BlurLayout::Runs;
        const std::vector<float> runs = run(*this, ctx(), image, shape, config);
        const std::string where = fmt::format("{}x{}x{} radius {}", width, height, channels, planBlur(config).radius);
        EXPECT_TRUE(test::allNear(std::span<const float>(runs), std::span<const float>(tiles), kBlurLayoutTol,
                                  width * channels))
            << where;
        if (ctx().info().isCpu()) {
          EXPECT_EQ(runs, tiles) << where << " (CPU devices: bit for bit)";
        }
      }
}

// Auto picks runs on CPU devices whose local memory holds the runs row pass's lines, tiles everywhere else.
TEST(BlurLayoutChoice, RunsOnCpusWithEnoughLocalMemory) {
  DeviceInfo cpu, gpu;
  cpu.type = CL_DEVICE_TYPE_CPU, gpu.type = CL_DEVICE_TYPE_GPU;
  cpu.localMemBytes = gpu.localMemBytes = 48 * 1024;
  const ImageShape shape{2048, 2048, 4};
  EXPECT_EQ(resolveBlurLayout(BlurLayout::Auto, cpu, shape, 6), BlurLayout::Runs);
  EXPECT_EQ(resolveBlurLayout(BlurLayout::Auto, gpu, shape, 6), BlurLayout::Tiles);
  cpu.localMemBytes = 16 * 1024;  // 4 lines of 512 + 2r float4 texels do not fit
  EXPECT_EQ(resolveBlurLayout(BlurLayout::Auto, cpu, shape, 6), BlurLayout::Tiles);
  EXPECT_EQ(resolveBlurLayout(BlurLayout::Runs, gpu, shape, 6), BlurLayout::Runs);  // asked for: as asked
}

// A running-sum plan's boxes: running sums (tiles) and, on the runs layout, direct equal-weight passes for boxes up
// to BLUR_RUNS_MAX_BOX_RADIUS: the same filter, within the running sums' own tolerance of each other.
TEST_F(BlurKernels, RunsLayoutBoxesMatchRunningSums) {
  for (const auto& [width, height] : {std::pair<uint32_t, uint32_t>{97, 61}, {1, 1}, {300, 2}})
    for (uint32_t channels : {1u, 2u, 4u})
      for (BlurConfig config :
           {gaussianBlur(16.0f, 1.0f, BlurMethod::RunningSums), boxBlur(20, BlurMethod::RunningSums)}) {
        const ImageShape shape{width, height, channels};
        const std::vector<double> image = ref::blurImage(shape, Input::Random, width * 3 + channels);
        config.layout = BlurLayout::Tiles;
        const std::vector<float> sums = run(*this, ctx(), image, shape, config);
        config.layout = BlurLayout::Runs;
        const std::vector<float> direct = run(*this, ctx(), image, shape, config);
        EXPECT_TRUE(test::allNear(std::span<const float>(direct), std::span<const float>(sums), kBlurRunningTol,
                                  width * channels))
            << width << "x" << height << "x" << channels << " radius " << planBlur(config).radius;
      }
}

// Half moments from both layouts' column passes (vstore_half16_rte on runs, per texel on tiles): the same sums
// rounded to nearest even, so equal where the fp32 sums are (CPU devices), else at most one half ulp apart.
TEST_F(BlurKernels, HalfMomentsLayoutsAgree) {
  for (const auto& [width, height] : {std::pair<uint32_t, uint32_t>{67, 41}, {1, 1}, {130, 3}})
    for (MomentKind kind : {MomentKind::Vsm, MomentKind::Evsm4}) {
      std::vector<float> depth(size_t(width) * height);
      for (size_t i = 0; i < depth.size(); ++i) depth[i] = 2.0f + 7.0f * float((i * 7919) % 1000) / 1000.0f;
      const Buffer<float> depthBuffer(ctx(), std::span<const float>(depth));
      MomentsConfig moments;
      moments.kind = kind;
      moments.depthNear = 2.0f, moments.depthFar = 9.0f;
      moments.storage = MomentStorage::Float16;
      const ImageShape shape{width, height, momentChannels(kind)};
      std::vector<cl_half> results[2];
      for (BlurLayout layout : {BlurLayout::Tiles, BlurLayout::Runs}) {
        BlurConfig config = gaussianBlur(2.0f);
        config.layout = layout;
        Buffer<cl_half> out(ctx(), shape.count());
        Buffer<float> scratch(ctx(), blurMomentsScratch(ctx(), shape, config, MomentStorage::Float16, moments.kind));
        blurMoments(ctx(), depthBuffer, moments, out, scratch, width, height, config);
        results[layout == BlurLayout::Runs] = out.download(ctx());
      }
      for (size_t i = 0; i < results[0].size(); ++i) {
        const int bitsApart = std::abs(int(results[0][i]) - int(results[1][i]));  // same sign: moments >= 0 or < 0
        ASSERT_LE(bitsApart, ctx().info().isCpu() ? 0 : 1) << width << "x" << height << " texel " << i / shape.channels;
      }
    }
}

TEST_F(BlurKernels, RejectsSmallBuffers) {
  Buffer<float> small(ctx(), 10), big(ctx(), 100);
  EXPECT_THROW(blur(ctx(), small, big, big, {5, 5, 1}, gaussianBlur(1.0f)), std::invalid_argument);
  EXPECT_THROW(blur(ctx(), big, big, big, {5, 5, 3}, gaussianBlur(1.0f)), std::invalid_argument);
}

}  // namespace blur_test
}  // namespace penumbra
