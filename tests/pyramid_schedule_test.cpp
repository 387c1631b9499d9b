// Batched pyramid schedule against the per-level one, bit for bit: moment mips (1/2/4 channels) and
// min-max pyramids over 1x1, thin, prime, odd and large sizes, with the device's plan and with small tiles
// and local budgets that force many work-groups (halos) and many passes. Plus the planner's dispatch counts.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "host/cl/buffer.h"
#include "host/stages/pyramid.h"
#include "tests/support/cl_test.h"
#include "tests/support/random_images.h"

namespace penumbra {
namespace pyramid_schedule_test {
using test::kPoison;

struct Case {
  uint32_t width, height, channels;
  uint32_t tile = 0;        // 0: the device's plan
  uint64_t localBytes = 0;  // 0: the device's budget
  uint32_t group = 0;       // work-items per group, group x group (narrowed for thin levels); 0: the device's
};

std::string caseName(const ::testing::TestParamInfo<Case>& p) {
  return fmt::format("{}x{}_c{}_t{}_l{}_g{}", p.param.width, p.param.height, p.param.channels, p.param.tile,
                     p.param.localBytes, p.param.group);
}

// Elements whose bits differ, and elements still holding the poison.
template <class T>
void expectSameBits(const std::vector<T>& batched, const std::vector<T>& perLevel) {
  ASSERT_EQ(batched.size(), perLevel.size());
  size_t differ = 0, poisoned = 0;
  for (size_t i = 0; i < batched.size(); ++i) {
    differ += std::memcmp(&batched[i], &perLevel[i], sizeof(T)) != 0;
    poisoned += std::memcmp(&batched[i], &kPoison, sizeof(float)) == 0;
  }
  EXPECT_EQ(differ, 0u) << "of " << batched.size() << " elements";
  EXPECT_EQ(poisoned, 0u) << "elements never written";
}

PyramidConfig batched(const Case& c) { return {PyramidSchedule::Batched, c.tile, c.localBytes, c.group, c.group}; }

class PyramidScheduleMips : public test::ClTestWithParam<Case> {};

TEST_P(PyramidScheduleMips, BatchedEqualsPerLevel) {
  const Case c = GetParam();
  const ImageShape shape{c.width, c.height, c.channels};
  const std::vector<float> base = test::randomUnitImage(shape.count(), c.width * 7 + c.height);
  const size_t size = std::max<size_t>(1, pyramidLayout(c.width, c.height, 1).texels * c.channels);
  Buffer<float> in(ctx(), std::span<const float>(base)), reference(ctx(), size), mips(ctx(), size);
  reference.fill(ctx(), kPoison);
  mips.fill(ctx(), kPoison);
  computeMomentMips(ctx(), in, shape, reference, {PyramidSchedule::PerLevel});
  computeMomentMips(ctx(), in, shape, mips, batched(c));
  std::vector<float> expected = reference.download(ctx()), actual = mips.download(ctx());
  if (c.width * c.height == 1) expected.clear(), actual.clear();  // no mips: the buffer stays poisoned
  expectSameBits(actual, expected);
}

constexpr uint64_t kGpuLocal = 48 * 1024;  // the GPU row's budget

INSTANTIATE_TEST_SUITE_P(Pyramid, PyramidScheduleMips,
                         ::testing::Values(Case{1, 1, 2}, Case{1, 300, 1}, Case{300, 1, 4}, Case{257, 131, 2},
                                           Case{131, 257, 1}, Case{1021, 3, 4}, Case{97, 61, 4}, Case{2048, 2048, 2},
                                           Case{2048, 2048, 4}, Case{4096, 4096, 1}, Case{8192, 64, 2},
                                           // Many groups and passes on small images: 2-3 texel tiles, 0.25-4 KiB of
                                           // local memory, groups of many work-items (strided spans, barriers).
                                           Case{257, 131, 2, 2, 2048, 16}, Case{257, 131, 4, 3, 4096, 4},
                                           Case{1021, 3, 1, 3, 1024, 32}, Case{3, 1021, 2, 2, 1024, 16},
                                           Case{97, 61, 1, 2, 256, 8}, Case{1, 300, 4, 2, 64, 16},
                                           Case{257, 131, 1, 2, 2048, 1},
                                           // The GPU row's plans (48 KiB, 16/8/4-texel tiles, 32x32 work-items).
                                           Case{2048, 2048, 2, 4, kGpuLocal, 32}, Case{1000, 999, 2, 16, kGpuLocal, 32},
                                           Case{1000, 999, 4, 8, kGpuLocal, 16}, Case{8192, 64, 1, 4, kGpuLocal, 32},
                                           Case{4096, 4096, 1, 4, kGpuLocal, 32}),
                         caseName);

class PyramidScheduleMinMax : public test::ClTestWithParam<Case> {};

// channels == 0 marks an all-background map; otherwise 1 in 5 texels is background, 1 in 29 NaN.
TEST_P(PyramidScheduleMinMax, BatchedEqualsPerLevel) {
  const Case c = GetParam();
  const std::vector<float> base = test::randomDepthMap(c.width, c.height, c.width + 11 * c.height, c.channels == 0);
  const size_t size = pyramidLayout(c.width, c.height, 0).texels;
  Buffer<float> in(ctx(), std::span<const float>(base));
  Buffer<cl_float2> reference(ctx(), size), out(ctx(), size);
  reference.fill(ctx(), {{kPoison, kPoison}});
  out.fill(ctx(), {{kPoison, kPoison}});
  computeMinMaxPyramid(ctx(), in, c.width, c.height, reference, {PyramidSchedule::PerLevel});
  computeMinMaxPyramid(ctx(), in, c.width, c.height, out, batched(c));
  expectSameBits(out.download(ctx()), reference.download(ctx()));
}

INSTANTIATE_TEST_SUITE_P(Pyramid, PyramidScheduleMinMax,
                         ::testing::Values(Case{1, 1, 1}, Case{1, 300, 1}, Case{300, 1, 1}, Case{257, 131, 1},
                                           Case{1021, 3, 1}, Case{13, 9, 0}, Case{2048, 2048, 1}, Case{4096, 4096, 1},
                                           Case{8192, 64, 1}, Case{257, 131, 1, 2, 2048, 16},
                                           Case{1021, 3, 1, 3, 1024, 32}, Case{97, 61, 0, 2, 512, 8},
                                           Case{2048, 2048, 1, 4, kGpuLocal, 32}, Case{1000, 999, 1, 8, kGpuLocal, 16}),
                         caseName);

// Dispatches of the GPU row (48 KiB, tiles 16/8/4, a group per unit on 132 units) and their invariants.
TEST(PyramidPlanTest, DispatchCountsAndLocalMemory) {
  const std::vector<uint32_t> tiles{16, 8, 4};
  struct Expect {
    uint32_t width, height, texelBytes;
    size_t passes;
  };
  for (const Expect e :
       {Expect{2048, 2048, 4, 2}, Expect{2048, 2048, 8, 2}, Expect{2048, 2048, 16, 3}, Expect{4096, 4096, 4, 2},
        Expect{4096, 4096, 8, 2}, Expect{4096, 4096, 16, 3}, Expect{8192, 64, 8, 2}, Expect{1021, 1019, 8, 2}}) {
    const auto passes = planPyramid(e.width, e.height, e.texelBytes, kGpuLocal, tiles, 132);
    EXPECT_EQ(passes.size(), e.passes) << e.width << "x" << e.height << ", " << e.texelBytes << " bytes per texel";
    uint32_t next = 1;
    for (const PyramidPass& p : passes) {
      EXPECT_EQ(p.first, next);
      EXPECT_LE(p.evenBytes + p.oddBytes, kGpuLocal);
      next += p.count;
    }
    EXPECT_EQ(next, pyramidLayout(e.width, e.height, 0).levels.size());
    EXPECT_EQ(passes.back().groupsX * passes.back().groupsY, 1u) << "the tail is one work-group";
  }
  // Odd sizes need halos: 2^k (T + 1) - 1 texels k levels above a T-texel tile when every level is odd.
  const auto odd = planPyramid(1023, 1023, 4, 1 << 20, {8}, 1);
  ASSERT_GE(odd[0].count, 3u);
  const uint32_t span = (8 + 1) * (1u << (odd[0].count - 1)) - 1;  // the first level of the first pass
  EXPECT_EQ(odd[0].evenBytes, uint64_t{span} * span * 4);
  EXPECT_EQ(planPyramid(1, 1, 8, kGpuLocal, tiles, 132).size(), 0u);
  EXPECT_THROW(planPyramid(64, 64, 8, kGpuLocal, {}, 1), std::invalid_argument);
}

}  // namespace pyramid_schedule_test
}  // namespace penumbra
