// Moments stage against the double reference: every encoding on random depth with background (+inf),
// NaN, -inf and out-of-range texels, constant images, 1x1 and prime sizes; exponent clamps; MSM round trip.
#include "host/stages/moments.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <tuple>
#include <vector>

#include "host/cl/buffer.h"
#include "host/cl/kernel.h"
#include "tests/reference/moments_ref.h"
#include "tests/support/cl_test.h"
#include "tests/support/compare.h"

namespace penumbra {
namespace moments_test {
using test::ClTestWithParam;
using test::kPoison;
using test::Tolerance;

// fp32 normalisation ((d - near) * 1/range) is within ~3 ulp of the double value; squares double it.
constexpr Tolerance kVsmTol{1e-6, 1e-6};
// exp(c x) with c = 42 amplifies the ~2e-7 error of x by c: 1e-5 relative, 2e-5 for the square.
constexpr Tolerance kEvsmTol{1e-30, 3e-5};
// ESM's e^(80 (d - 1)) (the default exponent): d's fp32 rounding (~3 ulp) times 80, relative.
constexpr Tolerance kEsmTol{1e-6, 1e-5};
// The MSM transform sums terms up to ~80 with cancellation: absolute error ~ 80 * 4 * 6e-8.
constexpr Tolerance kMsmTol{5e-5, 0.0};
// The published 10-digit matrices are inverse to about 1e-7 (conditioning ~1e3 for b3, b4).
constexpr double kMsmRoundTripTol = 2e-4;

constexpr float kNear = 2.0f, kFar = 10.0f;

// Light depths over [near - 1, far + 1] with background, NaN, -inf and a few huge values mixed in.
std::vector<float> randomDepth(size_t count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> depth(kNear - 1.0f, kFar + 1.0f);
  std::vector<float> out(count);
  for (size_t i = 0; i < count; ++i) {
    switch (rng() % 16) {
      case 0:
        out[i] = std::numeric_limits<float>::infinity();
        break;
      case 1:
        out[i] = std::numeric_limits<float>::quiet_NaN();
        break;
      case 2:
        out[i] = -std::numeric_limits<float>::infinity();
        break;
      case 3:
        out[i] = (rng() % 2 ? 1.0f : -1.0f) * 3e38f;
        break;
      default:
        out[i] = depth(rng);
    }
  }
  return out;
}

MomentsConfig config(MomentKind kind) {
  MomentsConfig c;
  c.kind = kind;
  c.depthNear = kNear;
  c.depthFar = kFar;
  c.evsmPositive = 100.0f;  // clamped to 42: the worst case for the fp32 range
  c.evsmNegative = 7.5f;
  c.layers = {{0.0f, 0.3f}, {0.25f, 0.6f}, {0.55f, 1.0f}};
  return c;
}

Tolerance tolerance(MomentKind kind) {
  if (kind == MomentKind::Evsm2 || kind == MomentKind::Evsm4) return kEvsmTol;
  if (kind == MomentKind::Esm) return kEsmTol;
  return kind == MomentKind::Msm ? kMsmTol : kVsmTol;
}

struct Case {
  MomentKind kind;
  uint32_t width, height;
  bool constant;
};

class MomentsTest : public ClTestWithParam<Case> {};

TEST_P(MomentsTest, MatchesReference) {
  const Case c = GetParam();
  const MomentsConfig cfg = config(c.kind);
  std::vector<float> depth = randomDepth(size_t(c.width) * c.height, c.width * 131 + c.height);
  if (c.constant) std::fill(depth.begin(), depth.end(), 5.0f);
  Buffer<float> depthBuffer(ctx(), std::span<const float>(depth));
  Buffer<float> out(ctx(), depth.size() * momentChannels(c.kind) * momentPlanes(cfg));
  out.fill(ctx(), kPoison);
  computeMoments(ctx(), depthBuffer, c.width, c.height, cfg, out);
  const std::vector<float> actual = out.download(ctx());
  const std::vector<double> expected = ref::moments(depth, cfg);
  EXPECT_TRUE(test::allNear(std::span<const float>(actual), std::span<const double>(expected), tolerance(c.kind)));
}

std::vector<Case> cases() {
  std::vector<Case> out;
  for (MomentKind kind :
       {MomentKind::Vsm, MomentKind::Evsm2, MomentKind::Evsm4, MomentKind::Lvsm, MomentKind::Msm, MomentKind::Esm})
    for (auto [w, h, constant] : {std::tuple{1u, 1u, false}, {97u, 61u, false}, {64u, 32u, false}, {13u, 7u, true}})
      out.push_back({kind, w, h, constant});
  return out;
}

std::string caseName(const ::testing::TestParamInfo<Case>& info) {
  static const char* const kNames[] = {"Vsm", "Evsm2", "Evsm4", "Lvsm", "Msm", "Esm"};
  return fmt::format("{}_{}x{}{}", kNames[int(info.param.kind)], info.param.width, info.param.height,
                     info.param.constant ? "_constant" : "");
}

INSTANTIATE_TEST_SUITE_P(Moments, MomentsTest, ::testing::ValuesIn(cases()), caseName);

// The reference of computeMomentsReduced: each block's mean of the per-texel reference moments, texels beyond the map
// as an empty texel's (+inf depth).
std::vector<double> blockMeans(const std::vector<float>& depth, uint32_t width, uint32_t height,
                               const MomentsConfig& cfg, uint32_t factor) {
  const std::vector<double> texel = ref::moments(depth, cfg);
  const std::vector<double> empty = ref::moments({std::numeric_limits<float>::infinity()}, cfg);
  const size_t channels = momentChannels(cfg.kind);
  const uint32_t outWidth = reducedExtent(width, factor), outHeight = reducedExtent(height, factor);
  std::vector<double> out(size_t(outWidth) * outHeight * channels, 0.0);
  for (uint32_t y = 0; y < outHeight; ++y)
    for (uint32_t x = 0; x < outWidth; ++x)
      for (uint32_t j = y * factor; j < (y + 1) * factor; ++j)
        for (uint32_t i = x * factor; i < (x + 1) * factor; ++i)
          for (size_t c = 0; c < channels; ++c) {
            const double v = i < width && j < height ? texel[(size_t(j) * width + i) * channels + c] : empty[c];
            out[(size_t(y) * outWidth + x) * channels + c] += v / double(factor * factor);
          }
  return out;
}

struct ReducedCase {
  MomentKind kind;
  uint32_t width, height, factor;
};

class MomentsReducedTest : public ClTestWithParam<ReducedCase> {};

// Block means of every linear encoding, on blocks that tile the map and on sizes the factor does not divide (the
// last blocks reach past the map), 1 x 1 maps and factor 1 (the plain stage's result).
TEST_P(MomentsReducedTest, MatchesBlockMeansOfTheReference) {
  const ReducedCase c = GetParam();
  const MomentsConfig cfg = config(c.kind);
  const std::vector<float> depth = randomDepth(size_t(c.width) * c.height, c.width * 17 + c.factor);
  const size_t outTexels = size_t(reducedExtent(c.width, c.factor)) * reducedExtent(c.height, c.factor);
  Buffer<float> depthBuffer(ctx(), std::span<const float>(depth));
  Buffer<float> out(ctx(), outTexels * momentChannels(c.kind));
  out.fill(ctx(), kPoison);
  computeMomentsReduced(ctx(), depthBuffer, c.width, c.height, cfg, c.factor, out);
  const std::vector<float> actual = out.download(ctx());
  const std::vector<double> expected = blockMeans(depth, c.width, c.height, cfg, c.factor);
  // A mean of factor^2 texels adds at most factor^2 fp32 roundings of its partial sums: 64 x 6e-8 relative at 8 x 8.
  Tolerance tol = tolerance(c.kind);
  tol.rel += 4e-6;
  tol.abs = std::max(tol.abs, 1e-6);
  EXPECT_TRUE(test::allNear(std::span<const float>(actual), std::span<const double>(expected), tol));
}

std::vector<ReducedCase> reducedCases() {
  std::vector<ReducedCase> out;
  for (MomentKind kind : {MomentKind::Vsm, MomentKind::Evsm2, MomentKind::Evsm4, MomentKind::Msm, MomentKind::Esm})
    for (auto [w, h, f] : {std::tuple{64u, 32u, 2u},
                           {97u, 61u, 4u},
                           {97u, 61u, 3u},
                           {1u, 1u, 4u},
                           {50u, 7u, 8u},
                           {64u, 48u, 8u},
                           {13u, 7u, 1u}})
      out.push_back({kind, w, h, f});
  return out;
}

std::string reducedName(const ::testing::TestParamInfo<ReducedCase>& info) {
  static const char* const kNames[] = {"Vsm", "Evsm2", "Evsm4", "Lvsm", "Msm", "Esm"};
  return fmt::format("{}_{}x{}_by{}", kNames[int(info.param.kind)], info.param.width, info.param.height,
                     info.param.factor);
}

INSTANTIATE_TEST_SUITE_P(Moments, MomentsReducedTest, ::testing::ValuesIn(reducedCases()), reducedName);

TEST(MomentsConfig, ClampsExponentsToStorage) {
  EXPECT_EQ(evsmClampExponent(100.0f, MomentStorage::Float32), 42.0f);
  EXPECT_EQ(evsmClampExponent(100.0f, MomentStorage::Float16), 5.54f);
  EXPECT_EQ(evsmClampExponent(-3.0f, MomentStorage::Float32), 0.0f);
  EXPECT_EQ(evsmClampExponent(std::nanf(""), MomentStorage::Float32), 0.0f);
  EXPECT_EQ(evsmClampExponent(3.0f, MomentStorage::Float16), 3.0f);
  // The clamps keep the second moment finite in the storage format.
  EXPECT_TRUE(std::isfinite(std::exp(2.0f * evsmMaxExponent(MomentStorage::Float32))));
  EXPECT_LT(std::exp(2.0 * evsmMaxExponent(MomentStorage::Float16)), 65504.0);
}

class MomentsKernels : public test::ClTest {};

TEST_F(MomentsKernels, RejectsBadConfiguration) {
  Buffer<float> depth(ctx(), 4), out(ctx(), 64);
  MomentsConfig bad = config(MomentKind::Vsm);
  bad.depthFar = bad.depthNear;
  EXPECT_THROW(computeMoments(ctx(), depth, 2, 2, bad, out), std::invalid_argument);
  bad = config(MomentKind::Lvsm);
  bad.layers = {{0.5f, 0.5f}};
  EXPECT_THROW(computeMoments(ctx(), depth, 2, 2, bad, out), std::invalid_argument);
  EXPECT_THROW(computeMoments(ctx(), depth, 4, 4, config(MomentKind::Vsm), out), std::invalid_argument);
  // Reduced: factors outside 1..64, LVSM, half storage, ESM in log space, an output too small for the blocks.
  const MomentsConfig vsm = config(MomentKind::Vsm);
  EXPECT_THROW(computeMomentsReduced(ctx(), depth, 2, 2, vsm, 0, out), std::invalid_argument);
  EXPECT_THROW(computeMomentsReduced(ctx(), depth, 2, 2, vsm, kMaxMomentsReduction + 1, out), std::invalid_argument);
  EXPECT_THROW(computeMomentsReduced(ctx(), depth, 2, 2, config(MomentKind::Lvsm), 2, out), std::invalid_argument);
  MomentsConfig half = vsm;
  half.storage = MomentStorage::Float16;
  EXPECT_THROW(computeMomentsReduced(ctx(), depth, 2, 2, half, 2, out), std::invalid_argument);
  MomentsConfig logEsm = config(MomentKind::Esm);
  logEsm.esmExponent = 200.0f;
  EXPECT_THROW(computeMomentsReduced(ctx(), depth, 2, 2, logEsm, 2, out), std::invalid_argument);
  Buffer<float> small(ctx(), 1);
  EXPECT_THROW(computeMomentsReduced(ctx(), depth, 2, 2, vsm, 1, small), std::invalid_argument);
}

TEST_F(MomentsKernels, MsmDecodeInvertsEncode) {
  constexpr int kCount = 257;
  std::vector<cl_float4> encoded(kCount);
  std::vector<double> expected;
  for (int i = 0; i < kCount; ++i) {
    const double d = double(i) / (kCount - 1);
    double q[4];
    ref::msmEncode(d, q);
    encoded[i] = {{float(q[0]), float(q[1]), float(q[2]), float(q[3])}};
    for (int k = 1; k <= 4; ++k) expected.push_back(std::pow(d, k));
  }
  Buffer<cl_float4> in(ctx(), std::span<const cl_float4>(encoded)), out(ctx(), kCount);
  Kernel(ctx(), "tests/kernels/moments_probe.cl", "moments_msm_decode_test", "moments")
      .args(in, out, uint32_t(kCount))
      .launch(kCount, 64);
  const std::vector<cl_float4> decoded = out.download(ctx());
  const std::span<const float> flat(&decoded[0].s[0], kCount * 4);
  EXPECT_TRUE(test::allNear(flat, std::span<const double>(expected), {kMsmRoundTripTol, 0.0}));
}

// 16-bit unorm packing (LVSM storage): the kernel rounds in fp32 to nearest even, the reference in double to
// nearest with ties away, so codes may differ by one where x * 65535 lies within fp32 rounding of a tie.
TEST_F(MomentsKernels, PackUnorm16MatchesReferenceWithinOneCode) {
  std::vector<float> values = {0.0f, 1.0f, -0.5f, 2.0f, std::numeric_limits<float>::quiet_NaN(),
                               std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
                               0.5f / 65535.0f, 1.0f / 65535.0f, 65534.5f / 65535.0f};
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (int i = 0; i < 997; ++i) values.push_back(unit(rng));
  const size_t offset = 5;
  Buffer<float> in(ctx(), std::span<const float>(values));
  Buffer<cl_ushort> out(ctx(), values.size() + offset);
  out.fill(ctx(), 0xBEEF);
  packMomentsUnorm16(ctx(), in, values.size(), out, offset);
  const std::vector<cl_ushort> codes = out.download(ctx());
  for (size_t i = 0; i < offset; ++i) EXPECT_EQ(codes[i], 0xBEEF) << "wrote before the offset";
  int exact = 0;
  for (size_t i = 0; i < values.size(); ++i) {
    const int expected = ref::unorm16(values[i]), got = codes[offset + i];
    EXPECT_LE(std::abs(got - expected), 1) << "value " << values[i];
    exact += got == expected;
  }
  EXPECT_GE(exact, static_cast<int>(values.size()) - 5);
  for (size_t i = 0; i < 7; ++i) EXPECT_EQ(codes[offset + i], ref::unorm16(values[i])) << values[i];  // not the ties
  EXPECT_THROW(packMomentsUnorm16(ctx(), in, values.size(), out, offset + 1), std::invalid_argument);
}

}  // namespace moments_test
}  // namespace penumbra
