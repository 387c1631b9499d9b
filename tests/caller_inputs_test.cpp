// The kernels that read the caller's images (kernels/caller_inputs.cl) against plain host code: the checks of
// `penumbra selftest`'s "caller" stage (tools/selftest/caller_checks.h), on PoCL.
#include <gtest/gtest.h>

#include "tests/support/cl_test.h"
#include "tests/support/compare.h"
#include "tools/selftest/caller_checks.h"

namespace penumbra {
namespace caller_inputs_test {

class CallerInputs : public test::ClTest {};

TEST_F(CallerInputs, DepthInEveryConventionWithAdversarialTexels) {
  EXPECT_TRUE(test::passes(selftest::callerDepth(ctx())));
}

TEST_F(CallerInputs, PositionsFromDepthAndNormalsFromPositions) {
  EXPECT_TRUE(test::passes(selftest::callerPositionsFromDepth(ctx())));
}

TEST_F(CallerInputs, PositionsAndNormalsOfTheCallers) { EXPECT_TRUE(test::passes(selftest::callerImages(ctx()))); }

TEST_F(CallerInputs, CopiesBetweenLayouts) { EXPECT_TRUE(test::passes(selftest::imageCopies(ctx()))); }

}  // namespace caller_inputs_test
}  // namespace penumbra
