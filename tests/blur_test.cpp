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
#include "tests/reference/blur_ref.h"
#include "tests/support/cl_test.h"
#include "tests/support/compare.h"

namespace penumbra {
namespace blur_test {
using test::kPoison;
using test::Tolerance;

// Direct sums of <= 2*32+1 fp32 products per pass of data in [0, 1]: <= 65 roundings of ~6e-8, twice.
constexpr Tolerance kDirectTol{5e-6, 1e-6};
// Running sums add and subtract one texel per step over segments of >= 128 steps: the drift is bounded
// by steps * eps relative to the window mean (~8e-6), three boxes per axis.
constexpr Tolerance kRunningTol{5e-5, 1e-5};
// Positive data spanning 1e20..1e30: only relative error is meaningful.
constexpr Tolerance kHugeRangeTol{0.0, 1e-5};
// Three boxes approximate the Gaussian: for data in [0, 1] the filtered values differ by a few percent
// of the local contrast at most (Wells 1986; Kovesi 2010).
constexpr Tolerance kBoxesVsGaussianTol{0.03, 0.0};
// The two direct layouts add each texel's taps in the same order with the same `sum += w * x`; they can differ
// only where a compiler contracts that into a fused multiply-add for one vector width and not the other: at most
// one rounding (6e-8 of the running sum, <= 1 for data in [0, 1]) per tap, 2 * 201 taps at radius 100. On CPU
// devices (PoCL, where both come from the same LLVM fmuladd) the test asks for bit equality.
constexpr Tolerance kLayoutTol{1e-5, 1e-5};

enum class Input { Random, Constant, HugeRange };

struct Case {
  std::string name;
  uint32_t width, height, channels;
  BlurConfig config;
  Input input = Input::Random;
};

std::vector<double> makeInput(const ImageShape& shape, Input kind, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<double> out(shape.count());
  for (double& v : out) {
    if (kind == Input::Constant)
      v = 0.625;
    else if (kind == Input::HugeRange)
      v = std::pow(10.0, 20.0 + 10.0 * unit(rng));
    else
      v = float(unit(rng));  // exactly representable in fp32
  }
  return out;
}

// What the kernels should compute: the plan's taps (direct) or its boxes (running sums).
std::vector<double> expected(const std::vector<double>& image, const ImageShape& shape, const BlurConfig& config) {
  const BlurPlan plan = planBlur(config);
  if (plan.direct)
    return ref::convolveSeparable(image, shape,
                                  config.filter == BlurFilter::Gaussian ? ref::gaussianTaps(config.sigma * config.scale)
                                                                        : ref::boxTaps(plan.radius));
  std::vector<double> out = image;
  for (int r : plan.boxRadii) out = ref::convolveSeparable(out, shape, ref::boxTaps(r));
  return out;
}

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

TEST_P(BlurTest, MatchesReference) {
  const Case& c = GetParam();
  const ImageShape shape{c.width, c.height, c.channels};
  const std::vector<double> image = makeInput(shape, c.input, c.width * 7 + c.height + c.channels);
  const std::vector<float> actual = run(*this, ctx(), image, shape, c.config);
  const Tolerance tol = c.input == Input::HugeRange ? kHugeRangeTol
                        : planBlur(c.config).direct ? kDirectTol
                                                    : kRunningTol;
  EXPECT_TRUE(test::allNear(std::span<const float>(actual), std::span<const double>(expected(image, shape, c.config)),
                            tol, c.width * c.channels));
}

BlurConfig gaussian(float sigma, float scale = 1.0f, BlurMethod method = BlurMethod::Auto) {
  return {BlurFilter::Gaussian, sigma, 0, scale, method};
}
BlurConfig box(int radius, BlurMethod method = BlurMethod::Auto) {
  return {BlurFilter::Box, 0.0f, radius, 1.0f, method};
}

const Case kCases[] = {
    {"Gauss1p5_97x61_c1", 97, 61, 1, gaussian(1.5f)},
    {"Gauss1p5_97x61_c2", 97, 61, 2, gaussian(1.5f)},
    {"Gauss1p5_97x61_c4", 97, 61, 4, gaussian(1.5f)},
    {"Gauss10_97x61_c2", 97, 61, 2, gaussian(10.0f)},
    {"Gauss2_scale2_3x200_c2", 3, 200, 2, gaussian(2.0f, 2.0f)},
    {"Gauss0_identity_5x4_c1", 5, 4, 1, gaussian(0.0f)},
    {"Gauss14_boxes_97x61_c1", 97, 61, 1, gaussian(14.0f)},
    {"Gauss40_boxes_300x2_c2", 300, 2, 2, gaussian(40.0f)},
    {"Box3_1x1_c2", 1, 1, 2, box(3)},
    {"Box7_256x3_c1", 256, 3, 1, box(7)},
    {"Box40_running_97x61_c2", 97, 61, 2, box(40)},
    {"Box5_running_130x70_c4", 130, 70, 4, box(5, BlurMethod::RunningSums)},
    {"Box100_direct_40x9_c1", 40, 9, 1, box(100, BlurMethod::Direct)},
    {"Box33_constant_61x67_c4", 61, 67, 4, box(33), Input::Constant},
    {"Gauss2_hugerange_50x37_c1", 50, 37, 1, gaussian(2.0f), Input::HugeRange},
};

INSTANTIATE_TEST_SUITE_P(Blur, BlurTest, ::testing::ValuesIn(kCases),
                         [](const ::testing::TestParamInfo<Case>& p) { return p.param.name; });

TEST(BlurPlan, BoxesMatchGaussianVariance) {
  for (float sigma : {11.0f, 14.0f, 25.0f, 80.0f}) {
    const BlurPlan plan = planBlur(gaussian(sigma));
    ASSERT_FALSE(plan.direct);
    double variance = 0.0;
    for (int r : plan.boxRadii) variance += ((2.0 * r + 1) * (2.0 * r + 1) - 1.0) / 12.0;
    // Odd widths move the variance in steps of ~2 * width / 12: within one box width of sigma^2.
    EXPECT_NEAR(variance, double(sigma) * sigma, 2.0 * sigma) << "sigma " << sigma;
  }
  EXPECT_TRUE(planBlur(gaussian(10.0f)).direct);
  EXPECT_EQ(planBlur(gaussian(2.0f, 1.5f)).radius, 9);
  EXPECT_EQ(planBlur(box(4)).weights.size(), 9u);
  EXPECT_THROW(planBlur(gaussian(-1.0f)), std::invalid_argument);
  EXPECT_THROW(planBlur(box(200, BlurMethod::Direct)), std::invalid_argument);
  EXPECT_THROW(planBlur(gaussian(1.0f, std::nanf(""))), std::invalid_argument);
}

class BlurKernels : public test::ClTest {};

TEST_F(BlurKernels, BoxesApproximateTheGaussian) {
  // Away from the borders only: clamping after every box is not clamping the Gaussian once.
  constexpr int kSigma = 12, kMargin = 4 * kSigma;
  const ImageShape shape{2 * kMargin + 37, 2 * kMargin + 23, 1};
  const std::vector<double> image = makeInput(shape, Input::Random, 5);
  const std::vector<float> actual = run(*this, ctx(), image, shape, gaussian(float(kSigma)));
  const std::vector<double> exact = ref::convolveSeparable(image, shape, ref::gaussianTaps(kSigma));
  std::vector<float> inner;
  std::vector<double> innerExact;
  for (uint32_t y = kMargin; y + kMargin < shape.height; ++y)
    for (uint32_t x = kMargin; x + kMargin < shape.width; ++x) {
      inner.push_back(actual[y * shape.width + x]);
      innerExact.push_back(exact[y * shape.width + x]);
    }
  EXPECT_TRUE(test::allNear(std::span<const float>(inner), std::span<const double>(innerExact), kBoxesVsGaussianTol));
}

TEST_F(BlurKernels, InPlaceMatchesOutOfPlace) {
  const ImageShape shape{45, 29, 2};
  const std::vector<double> image = makeInput(shape, Input::Random, 9);
  const std::vector<float> input(image.begin(), image.end());
  for (const BlurConfig& config : {gaussian(3.0f), gaussian(15.0f)}) {
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
      for (BlurConfig config : {gaussian(2.0f), box(3), gaussian(15.0f)})
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
  EXPECT_THROW(blurMoments(ctx(), depth, layered, out, scratch, 2, 2, gaussian(1.0f)), std::invalid_argument);
}

// ESM's log-space blur, in double around each output's largest tap, as the kernels define it: the D with
// e^(c D) = sum over rows of w_j (sum over columns of w_i e^(c d_ij)), clamp-to-edge, and the linear blur for c = 0.
std::vector<double> logBlurReference(const std::vector<double>& d, uint32_t width, uint32_t height,
                                     const std::vector<double>& taps, double c) {
  const int r = static_cast<int>(taps.size() / 2);
  const auto pass = [&](const std::vector<double>& in, bool rows) {
    std::vector<double> out(in.size());
    for (int y = 0; y < int(height); ++y)
      for (int x = 0; x < int(width); ++x) {
        const auto at = [&](int k) {
          return rows ? in[size_t(y) * width + std::clamp(x - r + k, 0, int(width) - 1)]
                      : in[size_t(std::clamp(y - r + k, 0, int(height) - 1)) * width + x];
        };
        double m = -INFINITY, sum = 0.0, linear = 0.0;
        for (int k = 0; k <= 2 * r; ++k) m = std::max(m, at(k));
        for (int k = 0; k <= 2 * r; ++k) sum += taps[k] * std::exp(c * (at(k) - m)), linear += taps[k] * at(k);
        out[size_t(y) * width + x] = c == 0.0 ? linear : m + std::log(sum) / c;
      }
    return out;
  };
  return pass(pass(d, true), false);
}

// fp32 rounds each pass's D to ~6e-8 and c (d - m) to ~6e-8 relative (a D error of 6e-8 whatever c). Measured worst
// over the cases below: see the test's record. Absolute, in normalised depth: a visibility error of at most c times it.
constexpr Tolerance kLogBlurTol{2e-6, 0.0};

// MomentKind::Esm's filtered depth D (e^(c D) the blurred e^(c d)) equals the double reference at the linear limit
// c = 0, in log space (kernels/shared/moments.h moments_log_mix: c = 0.5, 81, fp32's largest 1000, where e^(c d) itself
// would overflow even double) and as the linear blur of e^(c (d - 1)) (c = 20, 80: the fused direct and running-sum
// plans), on depth with background (+inf), NaN and out-of-range texels, 1x1 and thin maps; the log-space kernels refuse
// running-sum plans.
TEST_F(BlurKernels, EsmBlursInLogSpace) {
  std::mt19937 rng(23);
  std::uniform_real_distribution<float> depthDist(1.5f, 9.5f);
  for (const auto& [width, height] : {std::pair<uint32_t, uint32_t>{67, 41}, {1, 1}, {130, 3}}) {
    std::vector<float> depth(size_t(width) * height);
    for (size_t i = 0; i < depth.size(); ++i)
      depth[i] = i % 11 == 3 ? INFINITY : i % 17 == 5 ? std::nanf("") : depthDist(rng);
    const Buffer<float> depthBuffer(ctx(), std::span<const float>(depth));
    for (float c : {0.0f, 0.5f, 20.0f, 80.0f, 81.0f, 1000.0f})
      for (const BlurConfig& config : {gaussian(2.0f), box(2), gaussian(5.0f), gaussian(15.0f)}) {
        if (esmLogSpace(c) && !planBlur(config).direct) continue;  // refused, below
        MomentsConfig moments;
        moments.kind = MomentKind::Esm;
        moments.depthNear = 2.0f, moments.depthFar = 9.0f;
        moments.esmExponent = c;
        const ImageShape shape{width, height, 1};
        Buffer<float> out(ctx(), shape.count()),
            scratch(ctx(), blurMomentsScratch(ctx(), shape, config, MomentStorage::Float32, MomentKind::Esm));
        out.fill(ctx(), kPoison);
        scratch.fill(ctx(), kPoison);
        blurMoments(ctx(), depthBuffer, moments, out, scratch, width, height, config);
        std::vector<double> d(depth.size());
        for (size_t i = 0; i < depth.size(); ++i)
          d[i] = std::isfinite(depth[i]) ? std::clamp((depth[i] - 2.0) / 7.0, 0.0, 1.0) : 1.0;
        std::vector<double> reference;
        if (planBlur(config).direct) {
          reference = logBlurReference(
              d, width, height,
              config.filter == BlurFilter::Gaussian ? ref::gaussianTaps(config.sigma) : ref::boxTaps(config.radius), c);
        } else {  // running sums (c in [1, 80]): the plan's boxes one after another, on e^(c (d - 1)) in double
          std::vector<double> warped;
          for (double v : d) warped.push_back(std::exp(c * (v - 1.0)));
          for (double v : expected(warped, shape, config)) reference.push_back(1.0 + std::log(v) / c);
        }
        std::vector<float> got = out.download(ctx());
        if (!esmLogSpace(c))  // the map holds e^(c (d - 1)): its depth D
          for (float& v : got) v = 1.0f + std::log(v) / c;
        EXPECT_TRUE(test::allNear(std::span<const float>(got), std::span<const double>(reference), kLogBlurTol, width))
            << width << "x" << height << " c " << c << " radius " << planBlur(config).radius;
      }
  }
  MomentsConfig esm;
  esm.kind = MomentKind::Esm;
  esm.esmExponent = 200.0f;
  Buffer<float> depth(ctx(), 4), out(ctx(), 4), scratch(ctx(), 4);
  EXPECT_THROW(blurMoments(ctx(), depth, esm, out, scratch, 2, 2, gaussian(15.0f)), std::invalid_argument);
}

// Tiles and runs on the same input: odd, prime and thin sizes (rows shorter than a run, widths that are not a
// multiple of it, radii beyond the image), 1, 2 and 4 channels, radius 0 to 100.
TEST_F(BlurKernels, LayoutsAgree) {
  const std::pair<uint32_t, uint32_t> sizes[] = {{1, 1}, {97, 61}, {5, 131}, {523, 3}, {37, 29}};
  const BlurConfig configs[] = {
      gaussian(0.0f), gaussian(1.0f), box(1), gaussian(2.0f), box(13), gaussian(10.7f), box(100, BlurMethod::Direct)};
  for (const auto& [width, height] : sizes)
    for (uint32_t channels : {1u, 2u, 4u})
      for (BlurConfig config : configs) {
        const ImageShape shape{width, height, channels};
        const std::vector<double> image = makeInput(shape, Input::Random, width + height + channels);
        config.method = BlurMethod::Direct;  // the direct layouts (running-sum plans: RunsLayoutBoxesMatchRunningSums)
        config.layout = BlurLayout::Tiles;
        const std::vector<float> tiles = run(*this, ctx(), image, shape, config);
        config.layout = BlurLayout::Runs;
        const std::vector<float> runs = run(*this, ctx(), image, shape, config);
        const std::string where = fmt::format("{}x{}x{} radius {}", width, height, channels, planBlur(config).radius);
        EXPECT_TRUE(
            test::allNear(std::span<const float>(runs), std::span<const float>(tiles), kLayoutTol, width * channels))
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
      for (BlurConfig config : {gaussian(16.0f, 1.0f, BlurMethod::RunningSums), box(20, BlurMethod::RunningSums)}) {
        const ImageShape shape{width, height, channels};
        const std::vector<double> image = makeInput(shape, Input::Random, width * 3 + channels);
        config.layout = BlurLayout::Tiles;
        const std::vector<float> sums = run(*this, ctx(), image, shape, config);
        config.layout = BlurLayout::Runs;
        const std::vector<float> direct = run(*this, ctx(), image, shape, config);
        EXPECT_TRUE(
            test::allNear(std::span<const float>(direct), std::span<const float>(sums), kRunningTol, width * channels))
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
        BlurConfig config = gaussian(2.0f);
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
  EXPECT_THROW(blur(ctx(), small, big, big, {5, 5, 1}, gaussian(1.0f)), std::invalid_argument);
  EXPECT_THROW(blur(ctx(), big, big, big, {5, 5, 3}, gaussian(1.0f)), std::invalid_argument);
}

}  // namespace blur_test
}  // namespace penumbra
