// Reduce stage against the double reference: 1, 3 and 16 clusters over sample counts that are not
// multiples of the work-group (1, prime, > one group's chunk), with zero, negative and non-finite
// weights and samples; results must be bitwise identical across runs.
#include "host/stages/reduce.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "host/cl/buffer.h"
#include "tests/reference/reduce_ref.h"
#include "tests/support/cl_test.h"

namespace penumbra {
namespace reduce_test {

// fp32 sums of positive terms: serial runs of <= 64 samples then trees of depth <= 16; the error is
// bounded by (64 + 16) eps relative to the (all positive) sum.
constexpr double kSumRelTol = 80 * 6e-8;

struct Case {
  uint32_t count, clusters;
};

struct Inputs {
  std::vector<float> x, w, boundaries;
};

Inputs makeInputs(const Case& c) {
  std::mt19937 rng(c.count * 7 + c.clusters);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  Inputs in;
  for (uint32_t i = 0; i < c.count; ++i) {
    const uint32_t r = rng() % 50;
    in.x.push_back(r == 0 ? NAN : r == 1 ? INFINITY : unit(rng));
    in.w.push_back(r == 2 ? 0.0f : r == 3 ? -1.0f : r == 4 ? NAN : unit(rng) * 4.0f);
  }
  for (uint32_t k = 1; k < c.clusters; ++k) in.boundaries.push_back(float(k) / c.clusters);
  return in;
}

std::vector<LloydStats> run(Context& ctx, const Inputs& in, uint32_t clusters) {
  Buffer<float> x(ctx, std::span<const float>(in.x)), w(ctx, std::span<const float>(in.w));
  Buffer<float> boundaries(ctx, std::max<size_t>(1, in.boundaries.size()));
  boundaries.upload(ctx, std::span<const float>(in.boundaries));
  Buffer<LloydStats> out(ctx, clusters);
  out.fill(ctx, {test::kPoison, test::kPoison, test::kPoison, 0xdeadbeef});
  reduceLloydStats(ctx, x, w, in.x.size(), boundaries, clusters, out);
  return out.download(ctx);
}

class ReduceLloyd : public test::ClTestWithParam<Case> {};

TEST_P(ReduceLloyd, MatchesReferenceAndIsDeterministic) {
  const Case c = GetParam();
  const Inputs in = makeInputs(c);
  const std::vector<LloydStats> actual = run(ctx(), in, c.clusters);
  const std::vector<ref::LloydRef> expected = ref::lloydStats(in.x, in.w, in.boundaries);
  ASSERT_EQ(actual.size(), expected.size());
  for (size_t k = 0; k < expected.size(); ++k) {
    EXPECT_EQ(actual[k].samples, expected[k].samples) << "cluster " << k;
    EXPECT_NEAR(actual[k].sumW, expected[k].sumW, kSumRelTol * expected[k].sumW) << "cluster " << k;
    EXPECT_NEAR(actual[k].sumWX, expected[k].sumWX, kSumRelTol * expected[k].sumWX) << "cluster " << k;
    EXPECT_NEAR(actual[k].sumWX2, expected[k].sumWX2, kSumRelTol * expected[k].sumWX2) << "cluster " << k;
  }
  const std::vector<LloydStats> again = run(ctx(), in, c.clusters);
  for (size_t k = 0; k < actual.size(); ++k) {
    EXPECT_EQ(std::memcmp(&actual[k], &again[k], sizeof(LloydStats)), 0) << "cluster " << k << " not reproducible";
  }
}

INSTANTIATE_TEST_SUITE_P(Reduce, ReduceLloyd,
                         ::testing::Values(Case{1, 1}, Case{1000, 3}, Case{100003, 16}, Case{65536 * 5 + 7, 4},
                                           Case{0, 2}),
                         [](const ::testing::TestParamInfo<Case>& p) {
                           return fmt::format("n{}_k{}", p.param.count, p.param.clusters);
                         });

TEST(ReducePlan, FixedByCountAndValidated) {
  const ReduceParams p = planLloydReduction(100003, 3);
  EXPECT_EQ(p.groups, 98u);  // 1024 samples per group until 256 groups
  EXPECT_GE(size_t(p.groups) * p.chunk, 100003u);
  const ReduceParams big = planLloydReduction(4096u * 4096u, 3);
  EXPECT_EQ(big.groups, 256u);
  EXPECT_EQ(big.chunk, 65536u);
  EXPECT_THROW(planLloydReduction(10, 0), std::invalid_argument);
  EXPECT_THROW(planLloydReduction(10, REDUCE_MAX_CLUSTERS + 1), std::invalid_argument);
}

}  // namespace reduce_test
}  // namespace penumbra
