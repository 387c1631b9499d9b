// VSSM's per-pixel kernel (kernels/vssm.cl, vssm_visibility_receivers) against the double-precision reference
// (tools/selftest/reference/vssm_ref.cpp) on random and adversarial maps: planar blocks, NaN and empty texels, 1x1,
// thin and non-power-of-two maps, huge depth ranges, receivers outside the map; every subdivision scheme and SAT
// storage, the stacked-blocker PCF fallback and the narrowed search on and off. Plus the quad-tree's Child/Next links.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <ostream>
#include <random>
#include <string>
#include <vector>

#include "host/cl/kernel.h"
#include "host/techniques/vssm_maps.h"
#include "kernels/shared/light_view.h"
#include "tests/support/cl_test.h"
#include "tools/selftest/vssm_check.h"

namespace penumbra {
namespace vssm_test {
using test::kPoison;

using selftest::VssmCase;

std::string caseName(const ::testing::TestParamInfo<VssmCase>& p) { return p.param.name; }
void PrintTo(const VssmCase& c, std::ostream* os) { *os << c.name; }  // readable ctest names, not raw bytes

class VssmKernel : public test::ClTestWithParam<VssmCase> {};

// The cases, the run and the verdict are the selftest's (tools/selftest/vssm_check.h): `penumbra selftest` runs the
// same on a user's device.
TEST_P(VssmKernel, MatchesReference) {
  const VssmCase& c = GetParam();
  if (c.sat == VssmSatMode::Float64 && !ctx().info().fp64) GTEST_SKIP() << "no fp64 on " << ctx().info().name;
  const selftest::VssmOutcome o = selftest::runVssmCase(ctx(), c);
  EXPECT_EQ(o.failure(c), "");
  RecordProperty("flips", static_cast<int>(o.flips));
}

INSTANTIATE_TEST_SUITE_P(Vssm, VssmKernel, ::testing::ValuesIn(selftest::vssmCases()), caseName);

TEST(VssmQuadTree, ChildAndNextLinksWalkTheTreeDepthFirst) {
  for (uint32_t h = 1; h <= VSSM_MAX_LEVELS; ++h) {
    const std::vector<VssmNode> nodes = vssmQuadTree(h);
    ASSERT_EQ(nodes.size(), (std::pow(4.0, h + 1) - 1) / 3);
    // Always descending visits every node once, in order; never descending visits the root only.
    size_t visited = 0;
    for (uint32_t i = 0; i < nodes.size(); i = nodes[i].child != VSSM_NO_NODE ? nodes[i].child : nodes[i].next) {
      ASSERT_EQ(i, visited++);
    }
    EXPECT_EQ(visited, nodes.size());
    EXPECT_EQ(nodes[0].next, nodes.size());
    size_t leaves = 0;
    for (size_t i = 0; i < nodes.size(); ++i) {
      const VssmNode& n = nodes[i];
      leaves += n.child == VSSM_NO_NODE;
      EXPECT_EQ(n.next, i + (std::pow(4.0, h - n.level + 1) - 1) / 3) << "Next must skip the subtree";
      EXPECT_EQ(n.child == VSSM_NO_NODE, n.level == h);
      EXPECT_LT((n.cell & 0xffffu), 1u << n.level);
      EXPECT_LT((n.cell >> 16), 1u << n.level);
    }
    EXPECT_EQ(leaves, size_t(1) << (2 * h));
  }
  EXPECT_THROW(vssmQuadTree(0), std::invalid_argument);
  EXPECT_THROW(vssmQuadTree(VSSM_MAX_LEVELS + 1), std::invalid_argument);
}

}  // namespace vssm_test
}  // namespace penumbra
