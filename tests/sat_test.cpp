// SAT stage against the references: tiled and Hensley scans in every storage mode on random, constant,
// huge-range and non-finite images of awkward sizes (exact for fixed point), the box lookup against the
// exact integral, and one 2048^2 case. tools/bench/sat_precision.cpp regenerates docs/sat-precision.md.
#include "host/stages/sat.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "host/cl/buffer.h"
#include "host/cl/kernel.h"
#include "tests/reference/sat_ref.h"
#include "tests/support/cl_test.h"
#include "tests/support/compare.h"

namespace penumbra {
namespace sat_test {
using test::kPoison;
using test::Tolerance;

// Floating-point tables: a table entry is reached through at most ~2 * 32 in-tile additions plus one per
// tile along each axis, each rounding by at most eps times the running magnitude, which Sum|x - offset|
// bounds. Measured worst cases are below 1/4 of this (bounds are rarely attained).
constexpr double kTableOpsPerTile = 2.0;
double tableTolerance(const ImageShape& s, double epsilon, double magnitude) {
  const double ops = 2.0 * SAT_TILE + kTableOpsPerTile * (s.width + s.height) / SAT_TILE + std::log2(s.texels() + 1.0);
  return ops * epsilon * magnitude;
}
// The device mean is a float tree sum of float inputs: relative error ~ log2(n) eps.
constexpr double kMeanRelTol = 1e-5;

enum class Input { Random, Constant, HugeRange, NonFinite };

struct Case {
  std::string name;
  uint32_t width, height, channels, mode;
  SatAlgorithm algorithm = SatAlgorithm::Tiled;
  Input input = Input::Random;
  bool zeroMean = true;
};

std::vector<float> makeImage(const ImageShape& shape, Input kind, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<float> out(shape.count());
  for (float& v : out) {
    v = unit(rng);
    if (kind == Input::Constant) v = 0.75f;
    if (kind == Input::HugeRange) v = (v - 0.5f) * (rng() % 4 == 0 ? 1e30f : 1.0f);
    if (kind == Input::NonFinite && rng() % 97 == 0) v = rng() % 2 ? NAN : (rng() % 2 ? INFINITY : -INFINITY);
  }
  return out;
}

double magnitude(const std::vector<float>& image, const std::array<double, 4>& offset, uint32_t channels) {
  double sum = 0.0;
  for (size_t i = 0; i < image.size(); ++i)
    if (std::isfinite(image[i])) sum += std::abs(image[i] - offset[i % channels]);
  return sum;
}

template <class T>
void check(Context& ctx, const Case& c) {
  const ImageShape shape{c.width, c.height, c.channels};
  if (c.algorithm == SatAlgorithm::Tiled && !satTiledFits(ctx, satDesc(shape, satMode<T>())))
    GTEST_SKIP() << "the tiled kernels do not fit this device's local memory (the local-mem tests' small devices)";
  const std::vector<float> image = makeImage(shape, c.input, c.width * 31 + c.height * 7 + c.channels);
  Buffer<float> in(ctx, std::span<const float>(image)), offset(ctx, 4);
  Buffer<T> table(ctx, shape.count());
  table.fill(ctx, T(kPoison));
  offset.fill(ctx, kPoison);
  SatConfig config;
  config.algorithm = c.algorithm;
  config.zeroMean = c.zeroMean;
  computeSat(ctx, in, shape, table, offset, config);
  const std::vector<T> actual = table.download(ctx);
  const std::vector<float> off = offset.download(ctx);
  if constexpr (std::is_integral_v<T>) {
    EXPECT_EQ(off, std::vector<float>(4, 0.0f));
    const std::vector<T> expected =
        ref::satFixed<T>(image, shape, satDesc(shape, satMode<T>()).scale == 65536.0f ? 16 : 32);
    ASSERT_EQ(actual.size(), expected.size());
    size_t mismatches = 0;
    for (size_t i = 0; i < actual.size(); ++i) mismatches += actual[i] != expected[i];
    EXPECT_EQ(mismatches, 0u) << "fixed-point tables must be exact";
  } else {
    const std::array<double, 4> used{off[0], off[1], off[2], off[3]};
    if (c.zeroMean && satMode<T>() == SAT_MODE_FP32) {
      const std::array<double, 4> mean = ref::finiteMean(image, shape);
      for (uint32_t ch = 0; ch < c.channels; ++ch)
        EXPECT_NEAR(used[ch], mean[ch], kMeanRelTol * (std::abs(mean[ch]) + 1e-30)) << "channel " << ch;
    }
    const std::vector<double> expected = ref::satDouble(image, shape, used);
    const double eps = std::is_same_v<T, float> ? FLT_EPSILON : DBL_EPSILON;
    const Tolerance tol{tableTolerance(shape, eps, magnitude(image, used, c.channels)), 0.0, true};
    EXPECT_TRUE(test::allNear(std::span<const T>(actual), std::span<const double>(expected), tol,
                              size_t(c.width) * c.channels));
  }
}

class SatTest : public test::ClTestWithParam<Case> {};

TEST_P(SatTest, MatchesReference) {
  const Case& c = GetParam();
  switch (c.mode) {
    case SAT_MODE_FP32:
      return check<float>(ctx(), c);
    case SAT_MODE_FIXED32:
      return check<uint32_t>(ctx(), c);
    case SAT_MODE_FIXED64:
      return check<uint64_t>(ctx(), c);
    case SAT_MODE_FP64:
      return check<double>(ctx(), c);
  }
}

const char* algorithmName(SatAlgorithm algorithm) {
  return algorithm == SatAlgorithm::Tiled ? "Tiled" : algorithm == SatAlgorithm::Lines ? "Lines" : "Hensley";
}

std::vector<Case> cases() {
  struct Size {
    uint32_t w, h;
  };
  const Size sizes[] = {{1, 1}, {97, 61}, {64, 64}, {33, 130}, {300, 5}};
  const std::pair<uint32_t, uint32_t> modes[] = {
      {SAT_MODE_FP32, 2}, {SAT_MODE_FIXED32, 2}, {SAT_MODE_FIXED64, 1}, {SAT_MODE_FP64, 2}};
  const char* modeNames[] = {"Fp32", "Fixed32", "Fixed64", "Fp64"};
  std::vector<Case> out;
  for (auto [mode, channels] : modes)
    for (SatAlgorithm algorithm : {SatAlgorithm::Tiled, SatAlgorithm::Lines, SatAlgorithm::Hensley})
      for (Size s : sizes)
        out.push_back({fmt::format("{}_{}_{}x{}_c{}", modeNames[mode], algorithmName(algorithm), s.w, s.h, channels),
                       s.w, s.h, channels, mode, algorithm});
  // Adversarial inputs and the other channel counts, tiled (the production path).
  out.push_back({"Fp32_Tiled_97x61_c1_raw", 97, 61, 1, SAT_MODE_FP32, SatAlgorithm::Tiled, Input::Random, false});
  out.push_back({"Fp32_Tiled_45x70_c4_constant", 45, 70, 4, SAT_MODE_FP32, SatAlgorithm::Tiled, Input::Constant});
  out.push_back({"Fp32_Tiled_97x61_c1_hugerange", 97, 61, 1, SAT_MODE_FP32, SatAlgorithm::Tiled, Input::HugeRange});
  out.push_back({"Fp32_Tiled_97x61_c2_nonfinite", 97, 61, 2, SAT_MODE_FP32, SatAlgorithm::Tiled, Input::NonFinite});
  out.push_back({"Fp32_Hensley_50x40_c2_nonfinite", 50, 40, 2, SAT_MODE_FP32, SatAlgorithm::Hensley, Input::NonFinite});
  out.push_back(
      {"Fixed32_Tiled_97x61_c2_hugerange", 97, 61, 2, SAT_MODE_FIXED32, SatAlgorithm::Tiled, Input::HugeRange});
  out.push_back(
      {"Fixed32_Tiled_97x61_c2_nonfinite", 97, 61, 2, SAT_MODE_FIXED32, SatAlgorithm::Tiled, Input::NonFinite});
  out.push_back(
      {"Fixed64_Tiled_70x45_c1_nonfinite", 70, 45, 1, SAT_MODE_FIXED64, SatAlgorithm::Tiled, Input::NonFinite});
  out.push_back({"Fp64_Tiled_61x97_c2_hugerange", 61, 97, 2, SAT_MODE_FP64, SatAlgorithm::Tiled, Input::HugeRange});
  // One large case per mode family: fp32 (zero mean) and 32-bit fixed point.
  out.push_back({"Fp32_Tiled_2048x2048_c2", 2048, 2048, 2, SAT_MODE_FP32});
  out.push_back({"Fixed32_Tiled_2048x2048_c1", 2048, 2048, 1, SAT_MODE_FIXED32});
  return out;
}

INSTANTIATE_TEST_SUITE_P(Sat, SatTest, ::testing::ValuesIn(cases()),
                         [](const ::testing::TestParamInfo<Case>& p) { return p.param.name; });

// Box lookups (kernels/shared/sat.h) through the sat_test_box kernel, against the exact integral.
struct Box {
  float lox, loy, hix, hiy;
};

std::vector<Box> makeBoxes(const ImageShape& s, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> pos(-3.0f, float(std::max(s.width, s.height)) + 3.0f), extent(0.0f, 25.0f);
  const float w = float(s.width), h = float(s.height);
  std::vector<Box> boxes = {
      {0, 0, w, h}, {2, 3, 3, 4}, {1.5f, 2.25f, 1.5f, 9.0f}, {-9, -9, -1, -1}, {w + 1, 0, w + 5, h}};
  for (int i = 0; i < 200; ++i) {
    const float x = pos(rng), y = pos(rng);
    boxes.push_back({x, y, x + extent(rng), y + extent(rng)});
  }
  return boxes;
}

// Error of a box sum: at most 4 table entries' error per corner difference (the 16 bilinear weights sum
// to 1), quantization of every covered texel, and fp32 weighting of the differences.
constexpr double kLookupRelTol = 2e-6;  // 16 fp32 products of differences, relative to the texels they span

template <class T>
void checkLookup(Context& ctx, uint32_t channels) {
  const ImageShape shape{61, 47, channels};
  const std::vector<float> image = makeImage(shape, Input::Random, 77 + channels);
  Buffer<float> in(ctx, std::span<const float>(image)), offset(ctx, 4);
  Buffer<T> table(ctx, shape.count());
  computeSat(ctx, in, shape, table, offset);
  const SatTableDesc desc = satDesc(shape, satMode<T>());
  const std::vector<Box> boxes = makeBoxes(shape, channels);
  Buffer<cl_float4> boxBuffer(ctx, boxes.size());
  boxBuffer.upload(ctx, std::span<const cl_float4>(reinterpret_cast<const cl_float4*>(boxes.data()), boxes.size()));
  Buffer<float> sums(ctx, boxes.size() * channels), means(ctx, boxes.size() * channels);
  sums.fill(ctx, kPoison);
  means.fill(ctx, kPoison);
  Kernel(ctx, "tests/kernels/sat_probe.cl", "sat_test_box", "sat", satBuildOptions(desc))
      .args(table, desc, offset, boxBuffer, uint32_t(boxes.size()), sums, means)
      .launch(boxes.size(), 64);
  const std::vector<float> actualSums = sums.download(ctx), actualMeans = means.download(ctx);
  const std::vector<float> off = offset.download(ctx);
  const std::array<double, 4> used{off[0], off[1], off[2], off[3]};
  const double tableTol = std::is_integral_v<T>
                              ? 0.0
                              : tableTolerance(shape, std::is_same_v<T, float> ? FLT_EPSILON : DBL_EPSILON,
                                               magnitude(image, used, channels));
  for (size_t b = 0; b < boxes.size(); ++b) {
    const Box& box = boxes[b];
    const std::array<double, 4> exact = ref::boxIntegral(image, shape, box.lox, box.loy, box.hix, box.hiy);
    const double ax = std::clamp<double>(box.lox, 0, shape.width), bx = std::clamp<double>(box.hix, ax, shape.width);
    const double ay = std::clamp<double>(box.loy, 0, shape.height), by = std::clamp<double>(box.hiy, ay, shape.height);
    const double area = (bx - ax) * (by - ay), covered = (std::ceil(bx - ax) + 1) * (std::ceil(by - ay) + 1);
    const double quantum = std::is_integral_v<T> ? std::ldexp(0.5, -int(std::log2(desc.scale))) : 0.0;
    for (uint32_t ch = 0; ch < channels; ++ch) {
      const double tol = 4.0 * tableTol + quantum * covered + kLookupRelTol * (std::abs(exact[ch]) + covered);
      EXPECT_NEAR(actualSums[b * channels + ch], exact[ch], tol) << "box " << b << " channel " << ch;
      const double mean = area > 0 ? exact[ch] / area : 0.0;
      EXPECT_NEAR(actualMeans[b * channels + ch], mean, area > 0 ? tol / area : 0.0)
          << "box " << b << " channel " << ch;
    }
  }
}

class SatLookup : public test::ClTest {};

TEST_F(SatLookup, Fp32ZeroMean) { checkLookup<float>(ctx(), 2); }
TEST_F(SatLookup, Fixed32) { checkLookup<uint32_t>(ctx(), 2); }
TEST_F(SatLookup, Fixed64) { checkLookup<uint64_t>(ctx(), 1); }
TEST_F(SatLookup, Fp64) { checkLookup<double>(ctx(), 2); }

TEST(SatDesc, ValidatesAndDescribes) {
  const SatTableDesc d = satDesc({97, 61, 2}, SAT_MODE_FIXED32);
  EXPECT_EQ(d.tilesX, 4u);
  EXPECT_EQ(d.tilesY, 2u);
  EXPECT_EQ(d.scale, 65536.0f);
  EXPECT_EQ(satDesc({1, 1, 1}, SAT_MODE_FIXED64).scale, 4294967296.0f);
  EXPECT_EQ(satDesc({1, 1, 1}, SAT_MODE_FP32, 12).scale, 1.0f);
  EXPECT_THROW(satDesc({4, 4, 1}, SAT_MODE_FIXED32, 31), std::invalid_argument);
  EXPECT_THROW(satDesc({4, 4, 3}, SAT_MODE_FP32), std::invalid_argument);
  EXPECT_EQ(satBuildOptions(d), "-DSAT_MODE=1 -DSAT_CHANNELS=2");
  EXPECT_EQ(satFractionBits(SAT_MODE_FIXED32, 255.0 * 255.0, 1.0), 15);
  EXPECT_EQ(satFractionBits(SAT_MODE_FIXED32, 1.0, 1e-9), 30);
  EXPECT_EQ(satFractionBits(SAT_MODE_FIXED64, 4096.0 * 4096.0, 1.0), 38);
  EXPECT_THROW(satFractionBits(SAT_MODE_FIXED32, 1e6, 1e4), std::invalid_argument);
  EXPECT_THROW(satFractionBits(SAT_MODE_FP32, 1.0, 1.0), std::invalid_argument);
  DeviceInfo cpu, gpu;
  cpu.type = CL_DEVICE_TYPE_CPU;
  gpu.type = CL_DEVICE_TYPE_GPU;
  EXPECT_EQ(resolveSatAlgorithm(SatAlgorithm::Auto, cpu), SatAlgorithm::Lines);
  EXPECT_EQ(resolveSatAlgorithm(SatAlgorithm::Auto, gpu), SatAlgorithm::Tiled);
  EXPECT_EQ(resolveSatAlgorithm(SatAlgorithm::Hensley, gpu), SatAlgorithm::Hensley);
}

class SatKernels : public test::ClTest {};

TEST_F(SatKernels, ExplicitOffsetIsUsed) {
  const ImageShape shape{40, 33, 2};
  const std::vector<float> image = makeImage(shape, Input::Random, 3);
  Buffer<float> in(ctx(), std::span<const float>(image)), offset(ctx(), 4);
  Buffer<float> table(ctx(), shape.count());
  SatConfig config;
  config.offset = std::array<float, 4>{0.5f, 0.25f, 0.0f, 0.0f};
  computeSat(ctx(), in, shape, table, offset, config);
  EXPECT_EQ(offset.download(ctx()), (std::vector<float>{0.5f, 0.25f, 0.0f, 0.0f}));
  const std::vector<double> expected = ref::satDouble(image, shape, {0.5, 0.25, 0.0, 0.0});
  const std::vector<float> actual = table.download(ctx());
  const Tolerance tol{tableTolerance(shape, FLT_EPSILON, magnitude(image, {0.5, 0.25, 0, 0}, 2)), 0.0};
  EXPECT_TRUE(test::allNear(std::span<const float>(actual), std::span<const double>(expected), tol));
}

}  // namespace sat_test
}  // namespace penumbra

namespace penumbra {
namespace sat_test {

// Devices of 16 and 32 KiB with the GPU layouts forced: Auto takes the tiled scan where its static tiles fit and the
// line scans where they do not (4 channels: 17 to 20.5 KiB of 32-bit words, 41 KiB of 64-bit ones), and every mode
// and channel count still matches the reference.
TEST_F(SatKernels, AutoFitsSmallDevices) {
  for (uint64_t local : {16 * 1024, 32 * 1024}) {
    std::unique_ptr<Context> small = test::smallGpuContext(ctx(), local);
    EXPECT_EQ(satTiledFits(*small, satDesc({45, 70, 4}, SAT_MODE_FIXED64)), false) << local;  // 34,816 bytes and more
    EXPECT_EQ(satTiledFits(*small, satDesc({45, 70, 1}, SAT_MODE_FP32)), true) << local;      // 4,352 and 5,248
    for (uint32_t channels : {1u, 2u, 4u}) {
      SCOPED_TRACE(fmt::format("{} bytes, {} channels", local, channels));
      check<float>(*small, {"", 45, 70, channels, SAT_MODE_FP32, SatAlgorithm::Auto});
      check<uint32_t>(*small, {"", 45, 70, channels, SAT_MODE_FIXED32, SatAlgorithm::Auto});
      check<uint64_t>(*small, {"", 45, 70, channels, SAT_MODE_FIXED64, SatAlgorithm::Auto});
    }
  }
}

}  // namespace sat_test
}  // namespace penumbra
