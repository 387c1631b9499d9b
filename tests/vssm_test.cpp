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

// vssmCastersWindow: the casters' box widened by the reach and aligned outwards to whole blocks, within the map; one
// block at the origin without casters. Non-power-of-two maps, boxes at the map's edges, and a 1x1 map.
TEST(VssmCastersWindow, CoversTheBoxAndItsReachInWholeBlocksWithinTheMap) {
  EXPECT_EQ(vssmWindowReach(24.0f, 2), 48u + 4u + 2u);
  EXPECT_EQ(vssmWindowReach(0.3f, 1), 1u + 2u + 2u);
  EXPECT_EQ(vssmCastersWindow({0, 0, 0, 0}, 768, 500, 10, 4), (TexelWindow{0, 0, 4, 4}));  // no caster
  EXPECT_EQ(vssmCastersWindow({0, 0, 0, 0}, 3, 2, 10, 4), (TexelWindow{0, 0, 3, 2}));
  EXPECT_EQ(vssmCastersWindow({0, 0, 8, 8}, 1, 1, 10, 4), (TexelWindow{0, 0, 1, 1}));
  std::mt19937 random(7);
  for (int i = 0; i < 500; ++i) {
    const uint32_t width = 1 + random() % 700, height = 1 + random() % 700, block = 1u << (random() % 4);
    const uint32_t reach = random() % 80;
    const int x0 = int(random() % width) & ~7, y0 = int(random() % height) & ~7;
    const int x1 = x0 + 8 * (1 + int(random() % 20)), y1 = y0 + 8 * (1 + int(random() % 20));
    const TexelWindow w = vssmCastersWindow({x0, y0, x1, y1}, width, height, reach, block);
    const std::string at =
        fmt::format("{}x{} box {},{}..{},{} reach {} block {}", width, height, x0, y0, x1, y1, reach, block);
    EXPECT_GT(w.width, 0u) << at;
    EXPECT_GT(w.height, 0u) << at;
    EXPECT_LE(w.x + w.width, width) << at;
    EXPECT_LE(w.y + w.height, height) << at;
    EXPECT_EQ(w.x % block, 0u) << at;
    EXPECT_EQ(w.y % block, 0u) << at;
    EXPECT_TRUE(w.x + w.width == width || (w.x + w.width) % block == 0) << at;
    EXPECT_TRUE(w.y + w.height == height || (w.y + w.height) % block == 0) << at;
    // Every texel of the box and its reach that lies in the map, and no more than a block beyond.
    EXPECT_LE(int64_t{w.x}, std::max<int64_t>(0, x0 - int64_t{reach})) << at;
    EXPECT_LE(int64_t{w.y}, std::max<int64_t>(0, y0 - int64_t{reach})) << at;
    EXPECT_GE(int64_t{w.x} + w.width, std::min<int64_t>(width, x1 + int64_t{reach})) << at;
    EXPECT_GE(int64_t{w.y} + w.height, std::min<int64_t>(height, y1 + int64_t{reach})) << at;
    EXPECT_GT(int64_t{w.x} + block, int64_t{x0} - reach) << at;
    EXPECT_LT(int64_t{w.x} + w.width, int64_t{x1} + reach + block) << at;
  }
  EXPECT_THROW(vssmCastersWindow({0, 0, 8, 8}, 64, 64, 4, 0), std::invalid_argument);
}

// vssmWidestKernel: no kernel kernels/vssm.cl can take is wider (its widths are lv_penumbra_texels, replicated here,
// of a receiver and an occluder inside the map's depth range, clamped to [0.5, maxRadius]), and the bound is that of
// the widest pair (a caster at the near plane over a receiver at the far plane), for spot and sun views. A view
// without a usable range falls back to maxRadius.
TEST(VssmWidestKernel, BoundsEveryKernelOfTheMapsDepthRangeTightly) {
  const auto penumbra = [](const LightViewGpu& lv, double receiver, double occluder) {  // lv_penumbra_texels
    const double world = lv.kind == LIGHT_KIND_SPOT ? lv.lightSize * (receiver - occluder) / occluder
                                                    : lv.lightSize * (receiver - occluder);
    return std::max(world, 0.0) / (lv.kind == LIGHT_KIND_SPOT ? lv.texelScale * receiver : lv.texelScale);
  };
  std::mt19937 random(11);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (int i = 0; i < 200; ++i) {
    LightViewGpu lv{};
    lv.kind = i % 2 == 0 ? LIGHT_KIND_SPOT : LIGHT_KIND_DIRECTIONAL;
    lv.zNear = 0.05f + 5.0f * unit(random);
    lv.zFar = lv.zNear * (1.01f + 20.0f * unit(random));
    lv.texelScale = lv.kind == LIGHT_KIND_SPOT ? 2e-4f + 2e-3f * unit(random) : 1e-3f + 1e-2f * unit(random);
    lv.lightSize = lv.kind == LIGHT_KIND_SPOT ? 0.01f + 2.0f * unit(random) : 0.001f + 0.1f * unit(random);
    const float maxRadius = 4.0f + 200.0f * unit(random);
    const float bound = vssmWidestKernel(lv, maxRadius);
    double widest = 0.0;
    for (int r = 0; r <= 32; ++r)
      for (int o = 0; o <= r; ++o) {
        const double receiver = lv.zNear + (lv.zFar - lv.zNear) * r / 32.0;
        const double occluder = lv.zNear + (lv.zFar - lv.zNear) * o / 32.0;
        const float kernel = std::clamp(static_cast<float>(penumbra(lv, receiver, occluder)), 0.5f, maxRadius);
        EXPECT_LE(kernel, bound) << i << " receiver " << receiver << " occluder " << occluder;
        widest = std::max(widest, double{kernel});
      }
    EXPECT_LE(bound, widest * 1.002 + 0.02) << i;  // the corner pair is sampled
  }
  LightViewGpu bad{};
  bad.kind = LIGHT_KIND_SPOT, bad.zNear = 0.0f, bad.zFar = 10.0f, bad.texelScale = 1e-3f, bad.lightSize = 1.0f;
  EXPECT_EQ(vssmWidestKernel(bad, 64.0f), 64.0f);
  bad.zNear = 1.0f, bad.texelScale = NAN;
  EXPECT_EQ(vssmWidestKernel(bad, 64.0f), 64.0f);
}

}  // namespace vssm_test
}  // namespace penumbra
