// Moments stage against the double reference: every encoding on random depth with background (+inf),
// NaN, -inf and out-of-range texels, constant images, 1x1 and prime sizes; exponent clamps; MSM round trip.
#include "host/stages/moments.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <span>
#include <tuple>
#include <utility>
#include <vector>

#include "host/cl/buffer.h"
#include "host/cl/kernel.h"
#include "tests/support/cl_test.h"
#include "tests/support/compare.h"
#include "tools/selftest/probe_checks.h"
#include "tools/selftest/reference/cases.h"
#include "tools/selftest/reference/inputs.h"
#include "tools/selftest/reference/moments_ref.h"
#include "tools/selftest/stage_checks.h"

namespace penumbra {
namespace moments_test {
using test::ClTestWithParam;

using Case = ref::MomentsCase;

class MomentsTest : public ClTestWithParam<Case> {};

// The check is `penumbra selftest`'s (tools/selftest/stage_checks.h): the same input, reference and margin.
TEST_P(MomentsTest, MatchesReference) {
  EXPECT_TRUE(test::passes(selftest::checkMoments(ctx(), GetParam(), MomentStorage::Float32).comparison));
}

std::string caseName(const ::testing::TestParamInfo<Case>& info) { return info.param.name(); }

INSTANTIATE_TEST_SUITE_P(Moments, MomentsTest, ::testing::ValuesIn(ref::momentsCases()), caseName);

using ReducedCase = ref::MomentsReducedCase;

class MomentsReducedTest : public ClTestWithParam<ReducedCase> {};

// Block means of every linear encoding, on blocks that tile the map and on sizes the factor does not divide (the
// last blocks reach past the map), 1 x 1 maps and factor 1 (the plain stage's result).
TEST_P(MomentsReducedTest, MatchesBlockMeansOfTheReference) {
  EXPECT_TRUE(test::passes(selftest::checkMomentsReduced(ctx(), GetParam()).comparison));
}

std::string reducedName(const ::testing::TestParamInfo<ReducedCase>& info) { return info.param.name(); }

INSTANTIATE_TEST_SUITE_P(Moments, MomentsReducedTest, ::testing::ValuesIn(ref::momentsReducedCases()), reducedName);

// VSM's 2 x 2 blocks on CPU devices (moments_vsm_reduced2_rows, 8 blocks per work-item) against the per-block kernel
// the GPU layouts run: bit for bit on a CPU device, background and NaN texels included, on sizes with blocks past the
// map's edge and rows shorter than 8 blocks.
class MomentsReducedLayouts : public test::ClTest {};

TEST_F(MomentsReducedLayouts, VsmRowsOfBlocksEqualThePerBlockKernel) {
  Context* cpu = &ctx();
  auto gpu = test::smallGpuContext(ctx(), ctx().info().localMemBytes);
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> uniform(1.0f, 9.0f);
  for (const auto& [width, height] :
       {std::pair<uint32_t, uint32_t>{64, 32}, {97, 61}, {130, 3}, {2, 2}, {1, 1}, {33, 18}}) {
    std::vector<float> depth(size_t(width) * height);
    for (size_t i = 0; i < depth.size(); ++i)
      depth[i] = i % 11 == 3 ? std::numeric_limits<float>::infinity() : i % 13 == 5 ? std::nanf("") : uniform(rng);
    MomentsConfig config = ref::momentsCaseConfig(MomentKind::Vsm);
    config.depthNear = 2.0f, config.depthFar = 8.0f;  // depths outside clamp
    const size_t blocks = size_t(reducedExtent(width, 2)) * reducedExtent(height, 2);
    std::vector<float> results[2];
    for (int layout = 0; layout < 2; ++layout) {
      Context& ctx = layout == 0 ? *cpu : *gpu;
      Buffer<float> in(ctx, std::span<const float>(depth)), out(ctx, blocks * 2);
      out.fill(ctx, test::kPoison);
      computeMomentsReduced(ctx, in, width, height, config, 2, out);
      results[layout] = out.download(ctx);
    }
    if (cpu->info().isCpu()) {
      EXPECT_EQ(results[0], results[1]) << width << "x" << height;
    }
  }
}

// A window of the map (TexelWindow: vssm's SAT around its casters) has the moments of the map cropped to it, bit for
// bit: per texel and over blocks (2 x 2 through the CPU rows kernel, 3 x 3 with blocks past the window's edge), for VSM
// and EVSM4, inside the map and at its edges, on both layouts; a window that leaves the map is refused.
TEST_F(MomentsReducedLayouts, WindowsHaveTheMomentsOfTheCroppedMap) {
  auto gpu = test::smallGpuContext(ctx(), ctx().info().localMemBytes);
  std::mt19937 rng(23);
  std::uniform_real_distribution<float> uniform(1.0f, 9.0f);
  for (const auto& [width, height] : {std::pair<uint32_t, uint32_t>{97, 61}, {64, 32}, {130, 9}}) {
    std::vector<float> depth(size_t(width) * height);
    for (size_t i = 0; i < depth.size(); ++i)
      depth[i] = i % 11 == 3 ? std::numeric_limits<float>::infinity() : i % 13 == 5 ? std::nanf("") : uniform(rng);
    const TexelWindow windows[] = {
        {8, 4, 40, 5}, {0, 0, width, height}, {width - 13, height - 7, 13, 7}, {2, 1, 1, 1}, {16, 0, 34, height}};
    for (MomentKind kind : {MomentKind::Vsm, MomentKind::Evsm4})
      for (uint32_t factor : {1u, 2u, 3u})
        for (const TexelWindow& w : windows)
          for (Context* c : {&ctx(), gpu.get()}) {
            MomentsConfig config = ref::momentsCaseConfig(kind);
            config.depthNear = 2.0f, config.depthFar = 8.0f;
            std::vector<float> cropped(size_t(w.width) * w.height);
            for (uint32_t y = 0; y < w.height; ++y)
              std::copy_n(&depth[size_t(w.y + y) * width + w.x], w.width, &cropped[size_t(y) * w.width]);
            const size_t count =
                size_t(reducedExtent(w.width, factor)) * reducedExtent(w.height, factor) * momentChannels(kind);
            const auto run = [&](const std::vector<float>& map, uint32_t mw, uint32_t mh, const TexelWindow& window) {
              Buffer<float> in(*c, std::span<const float>(map)), out(*c, count);
              out.fill(*c, test::kPoison);
              if (factor == 1)
                computeMoments(*c, in, mw, mh, config, out, window);
              else
                computeMomentsReduced(*c, in, mw, mh, config, factor, out, window);
              return out.download(*c);
            };
            const std::vector<float> want = run(cropped, w.width, w.height, {});
            const std::vector<float> got = run(depth, width, height, w);
            ASSERT_EQ(want.size(), got.size());
            EXPECT_EQ(std::memcmp(want.data(), got.data(), want.size() * sizeof(float)), 0)
                << width << "x" << height << " window " << w.width << "x" << w.height << " at " << w.x << "," << w.y
                << " factor " << factor << " kind " << int(kind);
          }
    Buffer<float> in(ctx(), std::span<const float>(depth)), out(ctx(), depth.size() * 4);
    const MomentsConfig vsm = ref::momentsCaseConfig(MomentKind::Vsm);
    for (const TexelWindow& bad :
         {TexelWindow{width - 4, 0, 5, 1}, TexelWindow{0, height, 1, 1}, TexelWindow{0, 0, 3, 0}})
      EXPECT_THROW(computeMomentsReduced(ctx(), in, width, height, vsm, 2, out, bad), std::invalid_argument);
  }
}

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
  MomentsConfig bad = ref::momentsCaseConfig(MomentKind::Vsm);
  bad.depthFar = bad.depthNear;
  EXPECT_THROW(computeMoments(ctx(), depth, 2, 2, bad, out), std::invalid_argument);
  bad = ref::momentsCaseConfig(MomentKind::Lvsm);
  bad.layers = {{0.5f, 0.5f}};
  EXPECT_THROW(computeMoments(ctx(), depth, 2, 2, bad, out), std::invalid_argument);
  EXPECT_THROW(computeMoments(ctx(), depth, 4, 4, ref::momentsCaseConfig(MomentKind::Vsm), out), std::invalid_argument);
  // Reduced: factors outside 1..64, LVSM, half storage, ESM in log space, an output too small for the blocks.
  const MomentsConfig vsm = ref::momentsCaseConfig(MomentKind::Vsm);
  EXPECT_THROW(computeMomentsReduced(ctx(), depth, 2, 2, vsm, 0, out), std::invalid_argument);
  EXPECT_THROW(computeMomentsReduced(ctx(), depth, 2, 2, vsm, kMaxMomentsReduction + 1, out), std::invalid_argument);
  EXPECT_THROW(computeMomentsReduced(ctx(), depth, 2, 2, ref::momentsCaseConfig(MomentKind::Lvsm), 2, out),
               std::invalid_argument);
  MomentsConfig half = vsm;
  half.storage = MomentStorage::Float16;
  EXPECT_THROW(computeMomentsReduced(ctx(), depth, 2, 2, half, 2, out), std::invalid_argument);
  MomentsConfig logEsm = ref::momentsCaseConfig(MomentKind::Esm);
  logEsm.esmExponent = 200.0f;
  EXPECT_THROW(computeMomentsReduced(ctx(), depth, 2, 2, logEsm, 2, out), std::invalid_argument);
  Buffer<float> small(ctx(), 1);
  EXPECT_THROW(computeMomentsReduced(ctx(), depth, 2, 2, vsm, 1, small), std::invalid_argument);
}

// The probe checks are tools/selftest/probe_checks.h's, which `penumbra selftest` runs too.
TEST_F(MomentsKernels, MsmDecodeInvertsEncode) {
  const ref::Comparison c = selftest::msmDecode(ctx());
  EXPECT_TRUE(c.pass()) << c.mismatches << " of " << c.count << " powers off" << c.report;
}

// 16-bit unorm packing (LVSM storage): the kernel rounds in fp32 to nearest even, the reference in double to
// nearest with ties away, so codes may differ by one where x * 65535 lies within fp32 rounding of a tie.
TEST_F(MomentsKernels, PackUnorm16MatchesReferenceWithinOneCode) {
  const ref::Comparison c = selftest::packUnorm16(ctx());
  EXPECT_TRUE(c.pass()) << c.mismatches << " of " << c.count << " codes off" << c.report;
  Buffer<float> in(ctx(), 8);
  Buffer<cl_ushort> out(ctx(), 10);
  EXPECT_THROW(packMomentsUnorm16(ctx(), in, 8, out, 3), std::invalid_argument);  // 8 codes past offset 3 of 10
}

}  // namespace moments_test
}  // namespace penumbra
