// Pyramid stage (the default, batched schedule) against the double reference: moment mip chains (1/2/4
// channels, odd, prime, thin and 1x1 sizes; every level keeps the mean) and the min-max depth pyramid with
// background and NaN texels; the levels-only min-max pyramid's rows schedule against its batched one. The batched
// schedule against the per-level one: pyramid_schedule_test.cpp. The farthest depth over a disk (pcss's umbra test)
// against the texels the disk meets; the levels with a record of the map's background tiles.
#include "host/stages/pyramid.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <glm/glm.hpp>
#include <random>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "host/cl/buffer.h"
#include "host/cl/kernel.h"
#include "tests/support/cl_test.h"
#include "tests/support/compare.h"
#include "tests/support/random_images.h"
#include "tools/selftest/reference/cases.h"
#include "tools/selftest/reference/pyramid_ref.h"
#include "tools/selftest/stage_checks.h"

namespace penumbra {
namespace pyramid_test {

using Case = ref::PyramidCase;

std::string caseName(const ::testing::TestParamInfo<Case>& p) { return p.param.name(); }

class PyramidMips : public test::ClTestWithParam<Case> {};

// The checks are `penumbra selftest`'s (tools/selftest/stage_checks.h): every level within ref::kMipTol of the double
// area averages and its mean within ref::kMipMeanTol of the base's; min-max pyramids exact.
TEST_P(PyramidMips, MatchesReferenceAndKeepsTheMean) {
  EXPECT_TRUE(test::passes(selftest::checkMomentMips(ctx(), GetParam()).comparison));
}

// ESM's log-space mips (margin: ref::kLogMipTol): each level's D has e^(c D) the area average of e^(c D) over the level
// above, from the double reference of the linear mips applied to e^(c (d - 1)) (no overflow, and no underflow in double
// up to c = 700), at the linear limit c = 0, the paper's 80 and 600. fp32 rounds each level's D to ~6e-8 and its taps'
// c (d - m) to ~6e-8 relative; errors add over the levels. Absolute, in normalised depth.
class PyramidLogMips : public test::ClTest {};

TEST_F(PyramidLogMips, AverageTheExponentials) {
  for (const ref::PyramidCase& c : ref::logMipCases())
    for (float exponent : ref::kLogMipExponents)
      EXPECT_TRUE(test::passes(selftest::checkLogMips(ctx(), c, exponent).comparison)) << c.name() << " c " << exponent;
  Buffer<float> two(ctx(), 2), mips(ctx(), 1);
  EXPECT_THROW(computeLogMomentMips(ctx(), two, ImageShape{1, 1, 2}, mips, 80.0f), std::invalid_argument);
}

// The rows schedule builds levels-only min-max pyramids (LevelsRowsEqualBatched), not moment mips.
class PyramidRowsSchedule : public test::ClTest {};

TEST_F(PyramidRowsSchedule, BuildsMinMaxLevelsOnly) {
  Buffer<float> base(ctx(), 16), mips(ctx(), pyramidLayout(4, 4, 1).texels);
  EXPECT_THROW(computeMomentMips(ctx(), base, ImageShape{4, 4, 1}, mips, {PyramidSchedule::Rows}),
               std::invalid_argument);
}

INSTANTIATE_TEST_SUITE_P(Pyramid, PyramidMips, ::testing::ValuesIn(ref::momentMipCases()), caseName);

class PyramidMinMax : public test::ClTestWithParam<Case> {};

TEST_P(PyramidMinMax, MatchesReference) {
  EXPECT_TRUE(test::passes(selftest::checkMinMax(ctx(), GetParam()).comparison));
}

// Levels 1.. alone (computeMinMaxLevels), background and NaN the farthest depth: the reference's pyramid of the map
// with them replaced by a finite sentinel above every depth, the sentinel read back as +INFINITY. Exact, and the
// returned top is the last level.
TEST_P(PyramidMinMax, LevelsAboveTheMapMatchTheReference) {
  const Case c = GetParam();
  EXPECT_TRUE(test::passes(selftest::checkMinMaxLevels(ctx(), c).comparison));
  const PyramidLayout layout = pyramidLayout(c.width, c.height, 1);
  Buffer<float> in(ctx(), size_t(c.width) * c.height);
  Buffer<cl_float2> out(ctx(), std::max<size_t>(layout.texels, 1));
  EXPECT_THROW(computeMinMaxLevels(ctx(), in, c.width, c.height, out, {PyramidSchedule::PerLevel}),
               std::invalid_argument);
}

// The rows schedule (CPU devices' default) and the batched one (GPUs') give the same levels and top bit for bit, on
// every case; the rows schedule builds nothing but levels-only min-max pyramids.
TEST_P(PyramidMinMax, LevelsRowsEqualBatched) {
  const Case c = GetParam();
  const std::vector<float> base = ref::randomDepthMap(c.width, c.height, c.width + 7 * c.height, c.channels == 0);
  const PyramidLayout layout = pyramidLayout(c.width, c.height, 1);
  Buffer<float> in(ctx(), std::span<const float>(base));
  Buffer<cl_float2> rows(ctx(), std::max<size_t>(layout.texels, 1)), batched(ctx(), rows.size());
  rows.fill(ctx(), {{test::kPoison, test::kPoison}});
  batched.fill(ctx(), {{-test::kPoison, -test::kPoison}});
  const cl_float2 rowsTop = computeMinMaxLevels(ctx(), in, c.width, c.height, rows, {PyramidSchedule::Rows});
  const cl_float2 batchedTop = computeMinMaxLevels(ctx(), in, c.width, c.height, batched, {PyramidSchedule::Batched});
  EXPECT_EQ(std::memcmp(&rowsTop, &batchedTop, sizeof(cl_float2)), 0);
  const std::vector<cl_float2> a = rows.download(ctx()), b = batched.download(ctx());
  for (size_t i = 0; i < layout.texels; ++i)
    ASSERT_EQ(std::memcmp(&a[i], &b[i], sizeof(cl_float2)), 0)
        << "texel " << i << ": rows (" << a[i].s[0] << ", " << a[i].s[1] << "), batched (" << b[i].s[0] << ", "
        << b[i].s[1] << ")";
  if (c.width * c.height > 1) {  // a 1x1 map builds nothing
    Buffer<cl_float2> full(ctx(), pyramidLayout(c.width, c.height, 0).texels);
    EXPECT_THROW(computeMinMaxPyramid(ctx(), in, c.width, c.height, full, {PyramidSchedule::Rows}),
                 std::invalid_argument);
  }
}

// channels == 0 marks an all-background map.
INSTANTIATE_TEST_SUITE_P(Pyramid, PyramidMinMax, ::testing::ValuesIn(ref::minMaxCases()), caseName);

class PyramidBackground : public test::ClTest {};

// computeMinMaxLevels with a record of the map's background tiles (RasterTargets::backgroundTiles) gives the levels it
// gives without one, bit for bit, on maps whose first launch takes two levels (sides multiples of 32 and 4) and on one
// whose does not; the record is used: a tile with content marked as background changes the levels.
TEST_F(PyramidBackground, LevelsSkipTheBackgroundTilesTheSameBitForBit) {
  Context& ctx = this->ctx();
  for (const auto& [width, height] : {std::pair<uint32_t, uint32_t>{256, 128}, {32, 4}, {96, 200}, {100, 60}}) {
    std::vector<float> map = test::randomDepthMap(width, height, width + 3 * height);
    const uint32_t tilesX = (width + 7) / 8, tilesY = (height + 7) / 8;
    std::vector<uint32_t> record(size_t{tilesX} * tilesY, 0u);
    std::mt19937 rng(width * 7 + height);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    for (uint32_t ty = 0; ty < tilesY; ++ty)
      for (uint32_t tx = 0; tx < tilesX; ++tx) {
        if (unit(rng) < 0.4f) continue;  // a tile with content
        for (uint32_t y = 8 * ty; y < std::min(8 * ty + 8, height); ++y)
          for (uint32_t x = 8 * tx; x < std::min(8 * tx + 8, width); ++x) map[size_t{y} * width + x] = INFINITY;
        record[size_t{ty} * tilesX + tx] = unit(rng) < 0.9f ? 1u : 0u;  // a background tile the record may not know
      }
    const Buffer<float> depth(ctx, std::span<const float>(map));
    const PyramidLayout layout = pyramidLayout(width, height, 1);
    const auto levels = [&](const std::vector<uint32_t>* tiles) {
      Buffer<cl_float2> out(ctx, layout.texels);
      out.fill(ctx, {{test::kPoison, test::kPoison}});
      const Buffer<uint32_t> tileBuffer(ctx, std::span<const uint32_t>(tiles != nullptr ? *tiles : record));
      computeMinMaxLevels(ctx, depth, width, height, out, {PyramidSchedule::Rows},
                          tiles != nullptr ? &tileBuffer : nullptr);
      return out.download(ctx);
    };
    const std::vector<cl_float2> plain = levels(nullptr), skipped = levels(&record);
    EXPECT_EQ(std::memcmp(plain.data(), skipped.data(), plain.size() * sizeof(cl_float2)), 0) << width << "x" << height;
    if (width % 32 == 0 && height % 4 == 0) {  // the two-level launch reads the record
      std::vector<uint32_t> wrong(record.size(), 1u);
      const std::vector<cl_float2> lied = levels(&wrong);
      EXPECT_NE(std::memcmp(plain.data(), lied.data(), plain.size() * sizeof(cl_float2)), 0) << width << "x" << height;
    }
  }
}

// MinMaxLevels keeps which blocks of its levels hold background between builds and writes them only when they change:
// a map whose tiles go from background to content and back (and a build without a record between) gives, build after
// build, the levels a fresh build gives, bit for bit.
TEST_F(PyramidBackground, KeptBackgroundFollowsTheMapFromBuildToBuild) {
  Context& ctx = this->ctx();
  constexpr uint32_t kWidth = 256, kHeight = 128, kTilesX = kWidth / 8, kTilesY = kHeight / 8;
  const std::vector<float> content = test::randomDepthMap(kWidth, kHeight, 11);
  const auto frame = [&](uint32_t seed, std::vector<uint32_t>& record) {
    std::vector<float> map = content;
    std::mt19937 rng(seed);
    record.assign(size_t{kTilesX} * kTilesY, 0u);
    for (uint32_t t = 0; t < kTilesX * kTilesY; ++t) {
      if (rng() % 3 == 0) continue;  // content
      for (uint32_t y = 8 * (t / kTilesX); y < 8 * (t / kTilesX) + 8; ++y)
        for (uint32_t x = 8 * (t % kTilesX); x < 8 * (t % kTilesX) + 8; ++x) map[size_t{y} * kWidth + x] = INFINITY;
      record[t] = 1u;
    }
    return map;
  };
  MinMaxLevels levels;
  const PyramidLayout layout = pyramidLayout(kWidth, kHeight, 1);
  for (const auto& [seed, withRecord] :
       std::vector<std::pair<uint32_t, bool>>{{1, true}, {2, true}, {1, true}, {3, false}, {1, true}, {1, true}}) {
    std::vector<uint32_t> record;
    const std::vector<float> map = frame(seed, record);
    const Buffer<float> depth(ctx, std::span<const float>(map));
    const Buffer<uint32_t> tiles(ctx, std::span<const uint32_t>(record));
    levels.build(ctx, depth, kWidth, kHeight, withRecord ? &tiles : nullptr);
    Buffer<cl_float2> fresh(ctx, layout.texels);
    computeMinMaxLevels(ctx, depth, kWidth, kHeight, fresh, {PyramidSchedule::Rows});
    const std::vector<cl_float2> a = levels.pyramid().download(ctx), b = fresh.download(ctx);
    EXPECT_EQ(std::memcmp(a.data(), b.data(), b.size() * sizeof(cl_float2)), 0) << "map " << seed;
  }
}

// A record whose tiles hold content (RasterTargets::casterFreeTiles: receivers no caster reaches) takes their texels
// as background in every schedule: the levels and the top equal those of the map with those texels made background,
// bit for bit, for the rows schedule (two levels a launch, one, and the last texels of a row), the batched one on this
// device and on a small GPU, on exact, odd, thin and 1x1 maps; and MinMaxLevels' kept blocks follow records that change
// on the same map. A record read for the wrong tile, or only where all four tiles of a block agree, fails it.
TEST_F(PyramidBackground, TilesTakenAsBackgroundInEverySchedule) {
  Context& ctx = this->ctx();
  const std::unique_ptr<Context> gpu = test::smallGpuContext(ctx, 16 * 1024);
  for (const auto& [width, height] :
       {std::pair<uint32_t, uint32_t>{256, 128}, {32, 4}, {96, 200}, {100, 60}, {37, 9}, {300, 7}, {1, 1}}) {
    const std::vector<float> map = test::randomDepthMap(width, height, width * 5 + height);
    const uint32_t tilesX = (width + 7) / 8, tilesY = (height + 7) / 8;
    const auto recordOf = [&](uint32_t seed) {
      std::mt19937 rng(seed);
      std::vector<uint32_t> record(size_t{tilesX} * tilesY);
      for (uint32_t& r : record) r = rng() % 2;
      return record;
    };
    const auto levels = [&](Context& c, const std::vector<float>& m, const std::vector<uint32_t>* record,
                            PyramidSchedule schedule, cl_float2* top) {
      const PyramidLayout layout = pyramidLayout(width, height, 1);
      Buffer<cl_float2> out(c, std::max<size_t>(layout.texels, 1));
      out.fill(c, {{test::kPoison, test::kPoison}});
      const Buffer<float> depth(c, std::span<const float>(m));
      const Buffer<uint32_t> tiles(c, std::span<const uint32_t>(record != nullptr ? *record : recordOf(0)));
      *top = computeMinMaxLevels(c, depth, width, height, out, {schedule}, record != nullptr ? &tiles : nullptr);
      std::vector<cl_float2> all = out.download(c);
      all.resize(layout.texels);
      return all;
    };
    const auto same = [](const std::vector<cl_float2>& a, const std::vector<cl_float2>& b) {
      return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(cl_float2)) == 0;
    };
    for (uint32_t seed : {1u, 2u}) {
      const std::vector<uint32_t> record = recordOf(seed);
      std::vector<float> masked = map;
      for (uint32_t y = 0; y < height; ++y)
        for (uint32_t x = 0; x < width; ++x)
          if (record[size_t{y / 8} * tilesX + x / 8] != 0) masked[size_t{y} * width + x] = INFINITY;
      cl_float2 expectedTop, top;
      const std::vector<cl_float2> expected = levels(ctx, masked, nullptr, PyramidSchedule::Rows, &expectedTop);
      const std::string name = fmt::format("{}x{} record {}", width, height, seed);
      EXPECT_TRUE(same(levels(ctx, map, &record, PyramidSchedule::Rows, &top), expected)) << name << " rows";
      EXPECT_EQ(std::memcmp(&top, &expectedTop, sizeof top), 0) << name << " rows";
      EXPECT_TRUE(same(levels(ctx, map, &record, PyramidSchedule::Batched, &top), expected)) << name << " batched";
      EXPECT_EQ(std::memcmp(&top, &expectedTop, sizeof top), 0) << name << " batched";
      EXPECT_TRUE(same(levels(*gpu, map, &record, PyramidSchedule::Auto, &top), expected)) << name << " small GPU";
      if (width * height > 1) {
        EXPECT_FALSE(same(levels(ctx, map, nullptr, PyramidSchedule::Rows, &top), expected)) << name;  // it matters
      }
    }
    // Kept blocks between builds of one map whose records change (and a build without one).
    MinMaxLevels kept;
    const Buffer<float> depth(ctx, std::span<const float>(map));
    for (const auto& [seed, withRecord] :
         std::vector<std::pair<uint32_t, bool>>{{1, true}, {2, true}, {1, true}, {3, false}, {1, true}}) {
      const std::vector<uint32_t> record = recordOf(seed);
      const Buffer<uint32_t> tiles(ctx, std::span<const uint32_t>(record));
      kept.build(ctx, depth, width, height, withRecord ? &tiles : nullptr);
      cl_float2 top;
      const std::vector<cl_float2> fresh =
          levels(ctx, map, withRecord ? &record : nullptr, PyramidSchedule::Rows, &top);
      std::vector<cl_float2> built = kept.pyramid().download(ctx);
      built.resize(fresh.size());
      EXPECT_TRUE(same(built, fresh)) << width << "x" << height << " build with record " << seed << withRecord;
    }
  }
}

class PyramidDisk : public test::ClTest {};

// pyramid_far_in_disk (kernels/shared/pyramid.h) on maps of odd, thin and square sizes holding depths with background
// rectangles and scattered NaN over a slope: never nearer than the farthest texel whose square meets the disk (a nearer
// answer would make pcss write a false umbra), never farther than the square's lookup (pyramid_depth_range_of),
// `outside` where the square leaves the map, -inf for a disk of radius 0; and tighter than the square on many disks.
TEST_F(PyramidDisk, FarthestDepthHoldsEveryTexelTheDiskMeets) {
  Context& ctx = this->ctx();
  constexpr float kOutside = 1e30f;
  for (const auto& [width, height] : {std::pair<uint32_t, uint32_t>{1, 1}, {7, 5}, {97, 61}, {300, 7}, {512, 512}}) {
    std::mt19937 rng(width * 131 + height);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    std::vector<float> map(size_t{width} * height);
    for (uint32_t y = 0; y < height; ++y)
      for (uint32_t x = 0; x < width; ++x) {
        const bool background = (x / 37 + y / 23) % 11 == 10, nan = unit(rng) < 5e-5f;
        // A slope, so that a wider region holds a farther texel.
        const float ramp = static_cast<float>(x + 2 * y) / static_cast<float>(width + 2 * height);
        map[size_t{y} * width + x] = background ? INFINITY : nan ? NAN : 1.0f + 48.0f * ramp + unit(rng);
      }
    std::vector<cl_float4> disks;
    const std::vector<float> fixedRadii = {0.0f, 0.3f, 1.0f, 2.5f, 1000.0f};
    for (int k = 0; k < 400; ++k) {
      const float radius = k < 5 ? fixedRadii[static_cast<size_t>(k)] : unit(rng) * unit(rng) * 60.0f;
      disks.push_back({{-4.0f + unit(rng) * (static_cast<float>(width) + 8.0f),
                        -4.0f + unit(rng) * (static_cast<float>(height) + 8.0f), radius, 0.0f}});
    }
    MinMaxLevels pyramid;
    pyramid.build(ctx, Buffer<float>(ctx, std::span<const float>(map)), width, height);
    Buffer<float> depth(ctx, std::span<const float>(map));
    Buffer<cl_float4> diskBuffer(ctx, std::span<const cl_float4>(disks));
    Buffer<float> out(ctx, 2 * disks.size());
    out.fill(ctx, test::kPoison);
    Kernel(ctx, "tools/selftest/kernels/pyramid_probe.cl", "pyramid_disk_test", "test")
        .args(depth, pyramid.pyramid(), pyramid.levels(), pyramid.count(), width, height, diskBuffer,
              static_cast<uint32_t>(disks.size()), kOutside, out)
        .launch(disks.size(), 64);
    const std::vector<float> got = out.download(ctx);
    size_t inside = 0, finite = 0, tighter = 0;  // finite: the disk meets no background
    for (size_t i = 0; i < disks.size(); ++i) {
      const glm::vec2 c(disks[i].s[0], disks[i].s[1]);
      const float r = disks[i].s[2], disk = got[2 * i], square = got[2 * i + 1];
      const std::string where = fmt::format("{}x{} disk ({}, {}) radius {}", width, height, c.x, c.y, r);
      if (c.x - r < 0.0f || c.y - r < 0.0f || c.x + r > static_cast<float>(width) ||
          c.y + r > static_cast<float>(height)) {
        EXPECT_EQ(disk, kOutside) << where;
        continue;
      }
      if (r == 0.0f) {
        EXPECT_EQ(disk, -INFINITY) << where;
        continue;
      }
      ++inside;
      float farthest = -INFINITY;  // over the base texels whose square meets the disk; background and NaN +inf
      for (uint32_t y = 0; y < height; ++y)
        for (uint32_t x = 0; x < width; ++x) {
          const glm::vec2 near = glm::clamp(c, glm::vec2(x, y), glm::vec2(x + 1, y + 1)) - c;
          if (glm::dot(near, near) > r * r) continue;
          const float z = map[size_t{y} * width + x];
          farthest = std::max(farthest, std::isfinite(z) ? z : INFINITY);
        }
      EXPECT_GE(disk, farthest) << where;
      EXPECT_LE(disk, square) << where;
      finite += std::isfinite(farthest), tighter += std::isfinite(farthest) && disk < square;
    }
    if (width * height >= 512 * 512) {
      EXPECT_GT(finite, 100u);
      EXPECT_GT(tighter, finite / 2) << width << "x" << height;
    }
  }
}

TEST(PyramidLayoutTest, LevelsAndOffsets) {
  const PyramidLayout full = pyramidLayout(97, 61, 0);
  ASSERT_EQ(full.levels.size(), 7u);  // 97x61 48x30 24x15 12x7 6x3 3x1 1x1
  EXPECT_EQ(full.levels[5].width, 3u);
  EXPECT_EQ(full.levels[5].height, 1u);
  EXPECT_EQ(full.levels[1].offset, 97u * 61u);
  EXPECT_EQ(full.texels, 97u * 61 + 48 * 30 + 24 * 15 + 12 * 7 + 6 * 3 + 3 + 1);
  const PyramidLayout mips = pyramidLayout(97, 61, 1);
  EXPECT_EQ(mips.levels.size(), 6u);
  EXPECT_EQ(mips.levels[0].offset, 0u);
  EXPECT_TRUE(pyramidLayout(1, 1, 1).levels.empty());
  EXPECT_EQ(pyramidLayout(4096, 4096, 0).levels.size(), 13u);
}

}  // namespace pyramid_test
}  // namespace penumbra
