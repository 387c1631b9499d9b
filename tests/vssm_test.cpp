// VSSM's per-pixel kernel (kernels/vssm.cl, vssm_visibility_receivers) against the double-precision reference
// (tests/reference/vssm_ref.cpp) on random and adversarial maps: planar blocks, NaN and empty texels, 1x1, thin
// and non-power-of-two maps, huge depth ranges, receivers outside the map; every subdivision scheme and SAT
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
#include "tests/reference/vssm_ref.h"
#include "tests/support/cl_test.h"

namespace penumbra {
namespace vssm_test {
using test::kPoison;

// Receivers whose visibility may differ by more than kVisTol: fp32 kernel vs double reference flips the
// discrete decisions (E(x) >= t, sigma^2 < Threshold, a tap's depth test, the HSM level) for receivers within
// rounding of a threshold, and a flip moves visibility by up to one sub-kernel's share.
constexpr double kVisTol = 2e-3;        // fp32 moments: |z| <= 1 with ~1e-7 relative error, over <= 85 sub-kernels
constexpr double kMaxFlipShare = 0.02;  // at most 2% of receivers may differ by more than kVisTol
constexpr double kMaxPathShare = 0.03;  // ... or take another path
constexpr double kMeanVisTol = 2e-3;    // mean |difference| over all receivers

struct Case {
  std::string name;
  uint32_t width, height;
  float zNear, zFar;
  int searchScheme, shadeScheme;  // VSSM_SCHEME_*
  VssmSatMode sat = VssmSatMode::Fixed64;
  bool spot = true;
  float holes = 0.05f;  // share of NaN / empty texels
  double visTol = kVisTol;
  int diskStrips = 0;  // beyond the paper: disk kernels of at most this many strips
  double stacked = 0.1;  // beyond the paper: the stacked-blocker PCF fallback's threshold (the default; 0 = never)
  int narrowings = 2;    // beyond the paper: search-kernel narrowings (vssm-search adaptive, the default; 0 = full)
  int satReduce = 1;     // beyond the paper: the moments' SAT over blocks of satReduce^2 texels
};

std::string caseName(const ::testing::TestParamInfo<Case>& p) { return p.param.name; }
void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }  // readable ctest names, not raw bytes

// Planar occluder blocks over a tilted floor, with holes: what shadow maps hold, plus NaN.
std::vector<float> randomMap(const Case& c, std::mt19937& rng) {
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  const float range = c.zFar - c.zNear;
  const bool logDepth = c.zFar / c.zNear > 1e4f;  // huge ranges: depths spread over every decade
  auto depthAt = [&](float s) { return logDepth ? c.zNear * std::pow(c.zFar / c.zNear, s) : c.zNear + s * range; };
  std::vector<float> map(size_t(c.width) * c.height);
  for (uint32_t y = 0; y < c.height; ++y)
    for (uint32_t x = 0; x < c.width; ++x)
      map[y * c.width + x] = depthAt(0.8f + 0.15f * float(x + y) / (c.width + c.height));
  for (int b = 0; b < 6; ++b) {  // planar blocks
    const uint32_t x0 = uint32_t(rng() % c.width), y0 = uint32_t(rng() % c.height);
    const uint32_t x1 = std::min(c.width, x0 + 1 + uint32_t(rng() % std::max(1u, c.width / 2)));
    const uint32_t y1 = std::min(c.height, y0 + 1 + uint32_t(rng() % std::max(1u, c.height / 2)));
    const float z = depthAt(0.1f + 0.6f * unit(rng));
    for (uint32_t y = y0; y < y1; ++y)
      for (uint32_t x = x0; x < x1; ++x) map[y * c.width + x] = z;
  }
  for (float& z : map) {
    const float u = unit(rng);
    if (u < c.holes / 2)
      z = INFINITY;
    else if (u < c.holes)
      z = NAN;
    else if (u < c.holes + 0.03f)
      z = depthAt(unit(rng));  // isolated noise texels
  }
  return map;
}

// Half anywhere in front of the far plane, half on the map's own surfaces (where camera pixels are).
std::vector<ref::VssmReceiverIn> randomReceivers(const Case& c, const std::vector<float>& map, std::mt19937& rng,
                                                 size_t count) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<ref::VssmReceiverIn> out(count);
  const double range = c.zFar - c.zNear;
  for (size_t i = 0; i < count; ++i) {
    ref::VssmReceiverIn& r = out[i];
    r.u = -3.0 + unit(rng) * (c.width + 6.0), r.v = -3.0 + unit(rng) * (c.height + 6.0);
    r.depth = c.zNear + range * (0.3 + 0.7 * unit(rng));
    const int x = int(std::floor(r.u)), y = int(std::floor(r.v));
    const bool inside = x >= 0 && y >= 0 && x < int(c.width) && y < int(c.height);
    if (i % 2 == 1 && inside && std::isfinite(map[size_t(y) * c.width + x]))
      r.depth = map[size_t(y) * c.width + x] * (1.0 + 1e-4 * unit(rng));
    r.bias = range * 2e-3 * unit(rng), r.biasSlope = range * 1e-4 * unit(rng);
    r.seed = static_cast<uint32_t>(i);
  }
  return out;
}

ref::VssmSettings settingsFor(const Case& c) {
  ref::VssmSettings s;
  s.searchScheme = c.searchScheme, s.shadeScheme = c.shadeScheme;
  s.m = 5, s.n = 6, s.levels = 3, s.leafTaps = 2;
  s.planarMaxLit = 0.9;
  s.diskStrips = c.diskStrips;
  s.stackedSpread = c.stacked, s.stackedTaps = 8;
  s.searchNarrowings = c.narrowings;
  s.satReduce = c.satReduce;
  s.litVariance = 2.5e-5, s.contactDepth = 0.02 * (c.zFar - c.zNear), s.maxRadius = 24, s.minVariance = 1e-6;
  return s;
}

LightViewGpu lightFor(const Case& c) {
  LightViewGpu lv{};
  lv.kind = c.spot ? LIGHT_KIND_SPOT : LIGHT_KIND_DIRECTIONAL;
  lv.lightSize = c.spot ? 0.05f * (c.zFar - c.zNear) : 0.08f;
  lv.texelScale = c.spot ? 2.0f / c.width : 0.01f * (c.zFar - c.zNear);
  lv.zNear = c.zNear, lv.zFar = c.zFar;
  lv.width = static_cast<int>(c.width), lv.height = static_cast<int>(c.height);
  return lv;
}

struct KernelOut {
  std::vector<float> visibility;
  std::vector<cl_float4> debug;
};

KernelOut runKernel(Context& ctx, const Case& c, const std::vector<float>& map, const ref::VssmSettings& s,
                    const std::vector<ref::VssmReceiverIn>& receivers) {
  const LightViewGpu lv = lightFor(c);
  Buffer<float> depth(ctx, std::span<const float>(map));
  Buffer<LightViewGpu> lvBuffer(ctx, std::span<const LightViewGpu>(&lv, 1), CL_MEM_READ_ONLY);
  VssmMaps maps;
  maps.build(ctx, depth, c.width, c.height, c.zNear, c.zFar,
             {c.sat, float(s.maxRadius), uint32_t(s.levels), uint32_t(s.satReduce)});
  VssmParams p{};
  p.depthNear = maps.depthNear(), p.depthInvRange = maps.depthInvRange();
  p.litVariance = float(s.litVariance), p.contactDepth = float(s.contactDepth), p.maxRadius = float(s.maxRadius);
  p.minVariance = float(s.minVariance);
  p.searchScheme = uint32_t(s.searchScheme), p.shadeScheme = uint32_t(s.shadeScheme);
  p.searchDivisions = uint32_t(s.m), p.shadeDivisions = uint32_t(s.n), p.leafTaps = uint32_t(s.leafTaps);
  p.nodeCount = maps.nodeCount(), p.pyramidLevels = maps.levelCount();
  p.planarMaxLit = float(s.planarMaxLit);
  p.diskStrips = uint32_t(s.diskStrips);
  p.stackedSpread = float(s.stackedSpread), p.stackedTaps = uint32_t(s.stackedTaps);
  p.searchNarrowings = uint32_t(s.searchNarrowings);
  p.satReduce = maps.satReduce();
  std::vector<cl_float4> rx(receivers.size());
  std::vector<float> slopes(receivers.size());
  for (size_t i = 0; i < receivers.size(); ++i) {
    const ref::VssmReceiverIn& r = receivers[i];
    rx[i] = {{float(r.u), float(r.v), float(r.depth), float(r.bias)}};
    slopes[i] = float(r.biasSlope);
  }
  const uint32_t count = static_cast<uint32_t>(receivers.size());
  Buffer<cl_float4> rxBuffer(ctx, std::span<const cl_float4>(rx)), debug(ctx, count);
  Buffer<float> slopeBuffer(ctx, std::span<const float>(slopes)), visibility(ctx, count);
  visibility.fill(ctx, kPoison);
  Kernel kernel(ctx, "tests/kernels/vssm_probe.cl", "vssm_visibility_receivers", "vssm", maps.buildOptions());
  std::visit(
      [&](const auto& sat) {
        kernel
            .args(rxBuffer, slopeBuffer, count, depth, lvBuffer, sat, maps.satDesc(), maps.satOffset(), maps.hsm(),
                  maps.levels(), maps.nodes(), p, debug, visibility)
            .launch(count, 64);
      },
      maps.sat());
  return {visibility.download(ctx), debug.download(ctx)};
}

class VssmKernel : public test::ClTestWithParam<Case> {};

TEST_P(VssmKernel, MatchesReference) {
  const Case c = GetParam();
  if (c.sat == VssmSatMode::Float64 && !ctx().info().fp64) GTEST_SKIP() << "no fp64 on " << ctx().info().name;
  std::mt19937 rng(c.width * 131 + c.height * 7 + c.searchScheme * 3 + c.shadeScheme);
  const std::vector<float> map = randomMap(c, rng);
  const std::vector<ref::VssmReceiverIn> receivers = randomReceivers(c, map, rng, 600);
  const ref::VssmSettings settings = settingsFor(c);
  const KernelOut got = runKernel(ctx(), c, map, settings, receivers);
  ref::VssmLight light;
  const LightViewGpu lv = lightFor(c);
  light.spot = c.spot, light.lightSize = lv.lightSize, light.texelScale = lv.texelScale;
  light.zNear = c.zNear, light.zFar = c.zFar;
  const ref::VssmReference reference(map, c.width, c.height, light, settings);
  size_t flips = 0, paths = 0, subdivided = 0, stacked = 0;
  double sum = 0.0;
  std::string report;
  for (size_t i = 0; i < receivers.size(); ++i) {
    const ref::VssmResult want = reference.pixel(receivers[i]);
    const float vis = got.visibility[i];
    ASSERT_TRUE(vis >= 0.0f && vis <= 1.0f) << "receiver " << i << ": visibility " << vis;
    const double diff = std::abs(vis - want.visibility);
    sum += diff;
    subdivided += want.path == VSSM_PATH_SUBDIVIDED;
    stacked += want.path == VSSM_PATH_STACKED;
    if (diff > c.visTol && ++flips <= 5)
      report += fmt::format("\n  receiver {} ({:.3f}, {:.3f}, d {:.4g}): {} vs {} (paths {} / {})", i, receivers[i].u,
                            receivers[i].v, receivers[i].depth, vis, want.visibility, got.debug[i].s[3], want.path);
    paths += int(got.debug[i].s[3]) != want.path;
  }
  const double n = double(receivers.size());
  EXPECT_LE(paths, kMaxPathShare * n) << paths << " receivers took another path";
  EXPECT_LE(sum / n, kMeanVisTol);
  if (c.searchScheme != VSSM_SCHEME_NONE && c.width * c.height > 1) {
    EXPECT_GT(subdivided, 0u) << "no receiver took the subdivision path";
  }
  // The random maps' blocks overlap at several depths: some penumbra kernels hold stacked blockers.
  if (c.stacked > 0 && c.width * c.height > 1) {
    EXPECT_GT(stacked, 0u) << "no receiver took the stacked-blocker fallback";
  }
  if (c.stacked == 0) {
    EXPECT_EQ(stacked, 0u);
  }
}

constexpr int kU = VSSM_SCHEME_UNIFORM, kA = VSSM_SCHEME_ADAPTIVE, kN = VSSM_SCHEME_NONE;

INSTANTIATE_TEST_SUITE_P(
    Vssm, VssmKernel,
    ::testing::Values(
        Case{"mixed_61x37", 61, 37, 2.0f, 12.0f, kU, kA}, Case{"uniform_64x64", 64, 64, 2.0f, 12.0f, kU, kU},
        Case{"adaptive_64x64", 64, 64, 2.0f, 12.0f, kA, kA}, Case{"none_45x45", 45, 45, 2.0f, 12.0f, kN, kN},
        Case{"mixed_1x1", 1, 1, 2.0f, 12.0f, kU, kA}, Case{"mixed_200x3", 200, 3, 2.0f, 12.0f, kU, kA},
        Case{"mixed_huge_range", 53, 47, 0.01f, 1e6f, kU, kA},
        Case{"mixed_no_holes", 64, 48, 2.0f, 12.0f, kU, kA, VssmSatMode::Fixed64, true, 0.0f},
        Case{"mixed_mostly_holes", 40, 40, 2.0f, 12.0f, kU, kA, VssmSatMode::Fixed64, true, 0.6f},
        Case{"mixed_directional", 50, 50, 5.0f, 25.0f, kU, kA, VssmSatMode::Fixed64, false},
        Case{"mixed_fixed32", 48, 48, 2.0f, 12.0f, kU, kA, VssmSatMode::Fixed32, true, 0.05f, 2e-2},
        Case{"mixed_fp32", 48, 48, 2.0f, 12.0f, kU, kA, VssmSatMode::Float32, true, 0.05f, 2e-2},
        Case{"mixed_fp64", 48, 48, 2.0f, 12.0f, kU, kA, VssmSatMode::Float64},
        Case{"disk8_mixed_61x37", 61, 37, 2.0f, 12.0f, kU, kA, VssmSatMode::Fixed64, true, 0.05f, kVisTol, 8},
        Case{"disk4_uniform_64x64", 64, 64, 2.0f, 12.0f, kU, kU, VssmSatMode::Fixed64, true, 0.05f, kVisTol, 4},
        Case{"disk16_adaptive_64x64", 64, 64, 2.0f, 12.0f, kA, kA, VssmSatMode::Fixed64, true, 0.05f, kVisTol, 16},
        Case{"disk8_none_45x45", 45, 45, 2.0f, 12.0f, kN, kN, VssmSatMode::Fixed64, true, 0.05f, kVisTol, 8},
        Case{"disk8_mixed_1x1", 1, 1, 2.0f, 12.0f, kU, kA, VssmSatMode::Fixed64, true, 0.05f, kVisTol, 8},
        Case{"disk8_directional", 50, 50, 5.0f, 25.0f, kU, kA, VssmSatMode::Fixed64, false, 0.05f, kVisTol, 8},
        Case{"mixed_no_stacked_fallback", 61, 37, 2.0f, 12.0f, kU, kA, VssmSatMode::Fixed64, true, 0.05f, kVisTol, 0,
             0.0},
        Case{"mixed_full_search", 61, 37, 2.0f, 12.0f, kU, kA, VssmSatMode::Fixed64, true, 0.05f, kVisTol, 0, 0.1, 0},
        Case{"disk8_full_search", 61, 37, 2.0f, 12.0f, kU, kA, VssmSatMode::Fixed64, true, 0.05f, kVisTol, 8, 0.1, 0},
        // The SAT over blocks: 2 and 4 (vssm-sat-reduce auto's), 3 on sizes it does not divide, fixed32's bits.
        Case{"reduce2_disk8_mixed_61x37", 61, 37, 2.0f, 12.0f, kU, kA, VssmSatMode::Fixed64, true, 0.05f, kVisTol, 8,
             0.1, 2, 2},
        Case{"reduce4_mixed_64x64", 64, 64, 2.0f, 12.0f, kU, kA, VssmSatMode::Fixed64, true, 0.05f, kVisTol, 0, 0.1, 2,
             4},
        Case{"reduce3_disk8_uniform_50x47", 50, 47, 2.0f, 12.0f, kU, kU, VssmSatMode::Fixed64, true, 0.05f, kVisTol, 8,
             0.1, 2, 3},
        Case{"reduce2_disk8_fixed32", 48, 48, 2.0f, 12.0f, kU, kA, VssmSatMode::Fixed32, true, 0.05f, 2e-2, 8, 0.1, 2,
             2},
        Case{"reduce4_disk8_directional", 50, 50, 5.0f, 25.0f, kU, kA, VssmSatMode::Fixed64, false, 0.05f, kVisTol, 8,
             0.1, 2, 4},
        Case{"reduce2_mixed_1x1", 1, 1, 2.0f, 12.0f, kU, kA, VssmSatMode::Fixed64, true, 0.05f, kVisTol, 8, 0.1, 2, 2}),
    caseName);

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
