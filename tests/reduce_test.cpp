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
#include "tests/support/cl_test.h"
#include "tools/selftest/reference/cases.h"
#include "tools/selftest/reference/inputs.h"
#include "tools/selftest/reference/reduce_ref.h"
#include "tools/selftest/reference/tolerance.h"
#include "tools/selftest/stage_checks.h"

namespace penumbra {
namespace reduce_test {

using ref::kLloydSumRelTol;

using Case = ref::ReduceCase;

class ReduceLloyd : public test::ClTestWithParam<Case> {};

// The check is `penumbra selftest`'s (tools/selftest/stage_checks.h): counts exact, sums within ref::kLloydSumRelTol,
// the same bits on a second run.
TEST_P(ReduceLloyd, MatchesReferenceAndIsDeterministic) {
  EXPECT_TRUE(test::passes(selftest::checkLloyd(ctx(), GetParam()).comparison));
}

INSTANTIATE_TEST_SUITE_P(Reduce, ReduceLloyd, ::testing::ValuesIn(ref::reduceCases()),
                         [](const ::testing::TestParamInfo<Case>& p) { return p.param.name(); });

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
