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
#include "tests/support/cl_test.h"
#include "tests/support/compare.h"
#include "tools/selftest/probe_checks.h"
#include "tools/selftest/reference/cases.h"
#include "tools/selftest/reference/inputs.h"
#include "tools/selftest/reference/sat_ref.h"
#include "tools/selftest/reference/tolerance.h"
#include "tools/selftest/stage_checks.h"

namespace penumbra {
namespace sat_test {
using test::Tolerance;

using Case = ref::SatCase;

// The check is `penumbra selftest`'s (tools/selftest/stage_checks.h): fixed point exact, floating point within
// ref::satTableTolerance, the zero-mean offset within ref::kSatMeanRelTol; what does not apply to the device is
// skipped.
void check(Context& ctx, const Case& c) {
  try {
    EXPECT_TRUE(test::passes(selftest::checkSat(ctx, c).comparison)) << c.name;
  } catch (const selftest::NotApplicable& e) {
    GTEST_SKIP() << e.what();
  }
}

class SatTest : public test::ClTestWithParam<Case> {};

TEST_P(SatTest, MatchesReference) { check(ctx(), GetParam()); }

INSTANTIATE_TEST_SUITE_P(Sat, SatTest, ::testing::ValuesIn(ref::satCases()),
                         [](const ::testing::TestParamInfo<Case>& p) { return p.param.name; });

// Box lookups (kernels/shared/sat.h) through the sat_test_box probe against the exact integral:
// tools/selftest/probe_checks.h's, which `penumbra selftest` runs too.
template <class T>
void checkLookup(Context& ctx, uint32_t channels) {
  const ref::Comparison c = selftest::satLookup<T>(ctx, channels);
  EXPECT_TRUE(c.pass()) << c.mismatches << " of " << c.count << " box sums and means off" << c.report;
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
  const std::vector<float> image = ref::satImage(shape, ref::SatInput::Random, 3);
  Buffer<float> in(ctx(), std::span<const float>(image)), offset(ctx(), 4);
  Buffer<float> table(ctx(), shape.count());
  SatConfig config;
  config.offset = std::array<float, 4>{0.5f, 0.25f, 0.0f, 0.0f};
  computeSat(ctx(), in, shape, table, offset, config);
  EXPECT_EQ(offset.download(ctx()), (std::vector<float>{0.5f, 0.25f, 0.0f, 0.0f}));
  const std::vector<double> expected = ref::satDouble(image, shape, {0.5, 0.25, 0.0, 0.0});
  const std::vector<float> actual = table.download(ctx());
  const Tolerance tol{ref::satTableTolerance(shape, FLT_EPSILON, ref::satMagnitude(image, {0.5, 0.25, 0, 0}, 2)), 0.0};
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
      check(*small, {"", 45, 70, channels, SAT_MODE_FP32, SatAlgorithm::Auto});
      check(*small, {"", 45, 70, channels, SAT_MODE_FIXED32, SatAlgorithm::Auto});
      check(*small, {"", 45, 70, channels, SAT_MODE_FIXED64, SatAlgorithm::Auto});
    }
  }
}

}  // namespace sat_test
}  // namespace penumbra
