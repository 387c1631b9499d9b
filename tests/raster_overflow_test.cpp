// Bounded memory and hostile input: tiny queue capacities force the grow-and-retry path (results identical to a
// run that never overflowed), the hard maximum gives a clean error, and degenerate, NaN and infinite vertices,
// everything in one tile and many tiny triangles neither crash nor write out of bounds.
#include <gtest/gtest.h>

#include <string>

#include "host/cl/error.h"
#include "host/cl/profiler.h"
#include "host/views/raster_scene.h"
#include "raster/rasterizer.h"
#include "tests/raster_support.h"
#include "tests/support/cl_test.h"
#include "tools/selftest/reference/raster_ref.h"

namespace penumbra::test {
namespace raster_overflow_test {

class RasterOverflowTest : public ClTest {};

// A soup around the eye: big triangles crossing the near plane (clip fans need the extra records), many bins.
Scene clippedSoup() {
  Scene s = triangleSoup(300, 21, 2.0f, 1.5f);
  for (glm::vec3& p : s.positions) p.z += 2.0f;  // the eye sits at z = 4
  return s;
}

RasterView clippedView() { return perspectiveView(143, 91, {0, 0, 4}, {0, 0, 0}, 70.0f, 0.3f, 20.0f); }

TEST_F(RasterOverflowTest, TinyCapacitiesGrowAndMatch) {
  const Scene scene = clippedSoup();
  const RasterView view = clippedView();
  Rasterizer roomy(ctx());
  uploadScene(roomy, scene);
  const RasterOutput expected = drawPoisoned(ctx(), roomy, view);
  EXPECT_EQ(roomy.stats().retries, 0);
  const size_t big = 1 << 20;
  const RasterCapacities cases[] = {{1, big, big}, {big, 1, big}, {big, big, 1}, {1, 1, 1}};
  for (const RasterCapacities& caps : cases) {
    Rasterizer tight(ctx());
    uploadScene(tight, scene);
    tight.setCapacities(caps);
    const RasterOutput out = drawPoisoned(ctx(), tight, view);
    SCOPED_TRACE(fmt::format("capacities {} {} {}", caps.extraTriangles, caps.binEntries, caps.tileEntries));
    if (caps.tileEntries == 1 && caps.binEntries == 1) {
      EXPECT_GE(tight.stats().retries, 1);
    } else {
      EXPECT_EQ(tight.stats().retries, 1);  // the counters are exact: one growth suffices
    }
    EXPECT_EQ(out.ids, expected.ids);
    EXPECT_EQ(out.depth, expected.depth);
    EXPECT_EQ(tight.stats().binEntries, roomy.stats().binEntries);
    EXPECT_EQ(tight.stats().tileEntries, roomy.stats().tileEntries);
    EXPECT_EQ(tight.stats().trianglesSetUp, roomy.stats().trianglesSetUp);
    // Grown capacities are kept: the next draw needs no retry.
    drawPoisoned(ctx(), tight, view);
    EXPECT_EQ(tight.stats().retries, 0);
  }
  const RefRasterizer ref(scene, view);
  EXPECT_GT(ref.fannedTriangles(), 10u);
  const RasterComparison cmp = compareWithReference(expected, ref, view, 20.0);
  EXPECT_TRUE(matchesReference(cmp, cmp.covered / 200 + 2));
}

TEST_F(RasterOverflowTest, HardMaximumIsACleanError) {
  const Scene scene = clippedSoup();
  Rasterizer raster(ctx());
  uploadScene(raster, scene);
  RasterCapacities caps{1, 1, 1};
  caps.maxEntries = 64;
  raster.setCapacities(caps);
  RasterTargets targets;
  try {
    raster.draw(clippedView(), targets);
    FAIL() << "no error past the hard maximum";
  } catch (const ClError& e) {
    EXPECT_EQ(e.code(), CL_OUT_OF_RESOURCES);
    EXPECT_EQ(e.stage(), "raster");
    EXPECT_NE(std::string(e.what()).find("queue needs"), std::string::npos) << e.what();
  }
}

TEST_F(RasterOverflowTest, HostileVerticesAreDropped) {
  const float nan = std::nanf(""), inf = INFINITY;
  Scene scene = makeScene({{-1, -1, 0},
                           {1, -1, 0},
                           {0, 1, 0},  // 0: a good triangle
                           {nan, 0, 0},
                           {1, 1, 0},
                           {-1, 1, 0},  // 1: NaN
                           {inf, 0, 0},
                           {0, -inf, 0},
                           {0.5f, 0.5f, 0},  // 2: infinities
                           {0.2f, 0.2f, 0.5f},
                           {0.2f, 0.2f, 0.5f},  // 3: a point
                           {-1, 0, 0.2f},
                           {0, 0, 0.2f},
                           {1, 0, 0.2f},         // 4: collinear
                           {3e38f, -3e38f, 1}},  // 5: overflows in clip space
                          {{0, 1, 2}, {3, 4, 5}, {6, 7, 8}, {9, 10, 9}, {11, 12, 13}, {14, 0, 1}});
  const RasterView view = perspectiveView(61, 47, {0, 0, 3}, {0, 0, 0}, 60.0f, 0.1f, 10.0f);
  Rasterizer raster(ctx());
  uploadScene(raster, scene);
  const RasterOutput out = drawPoisoned(ctx(), raster, view);
  size_t good = 0;
  for (uint32_t id : out.ids) {
    ASSERT_TRUE(id == 0 || id == 5 || id == kNoTriangle) << id;
    good += id == 0;
  }
  EXPECT_GT(good, 200u);
  const RefRasterizer ref(scene, view);
  EXPECT_TRUE(matchesReference(compareWithReference(out, ref, view, 10.0), 4));
}

TEST_F(RasterOverflowTest, OutOfRangeIndexIsRejectedAtUpload) {
  Scene scene = makeScene({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 3}});
  Rasterizer raster(ctx());
  EXPECT_THROW(uploadScene(raster, scene), std::invalid_argument);
}

TEST_F(RasterOverflowTest, EverythingInOneTile) {
  // 3000 triangles overlapping inside one 8x8 tile: one fine work-group walks them all.
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> u(16.0f, 24.0f), z(-0.9f, 0.9f);
  std::vector<glm::vec3> p;
  std::vector<glm::uvec3> t;
  for (int i = 0; i < 3000; ++i) {
    for (int k = 0; k < 3; ++k) p.emplace_back(u(rng), u(rng), z(rng));
    t.emplace_back(3 * i, 3 * i + 1, 3 * i + 2);
  }
  const Scene scene = makeScene(p, t);
  RasterView view;
  view.projection = glm::ortho(0.0f, 37.0f, 0.0f, 29.0f, -1.0f, 1.0f);
  view.width = 37, view.height = 29;
  Rasterizer raster(ctx());
  uploadScene(raster, scene);
  const RasterOutput out = drawPoisoned(ctx(), raster, view);
  const RefRasterizer ref(scene, view);
  const RasterComparison cmp = compareWithReference(out, ref, view, 1.0);
  EXPECT_TRUE(matchesReference(cmp, 2));
  EXPECT_GT(cmp.covered, 50u);
}

TEST_F(RasterOverflowTest, ManyTinyTriangles) {
  // 250k triangles a few pixels across, the bulk of them invisible or smaller than a pixel.
  const Scene scene = triangleSoup(250000, 23, 1.6f, 0.01f);
  const RasterView view = perspectiveView(256, 192, {0, 0, 4.5f}, {0, 0, 0}, 50.0f, 0.5f, 20.0f);
  Rasterizer raster(ctx());
  uploadScene(raster, scene);
  raster.setCapacities(RasterCapacities{16, 1000, 1000});
  const RasterOutput out = drawPoisoned(ctx(), raster, view);
  EXPECT_GT(raster.stats().retries, 0);
  const RefRasterizer ref(scene, view);
  const RasterComparison cmp = compareWithReference(out, ref, view, 10.0);
  EXPECT_TRUE(matchesReference(cmp, cmp.covered / 100 + 2));
}

TEST_F(RasterOverflowTest, EveryLaunchIsProfiledUnderRaster) {
  Profiler profiler;
  ProfilerScope scope(ctx(), profiler);
  Rasterizer raster(ctx());
  uploadScene(raster, clippedSoup());
  drawPoisoned(ctx(), raster, clippedView());
  std::vector<std::string> names;
  for (const PassTime& pass : profiler.resolve()) names.push_back(pass.name);
  for (const char* kernel :
       {"setup_triangles", "bin_count", "bin_scan", "bin_fill", "coarse_count", "coarse_fill", "fine_raster"})
    EXPECT_NE(std::find(names.begin(), names.end(), std::string("raster/") + kernel), names.end()) << kernel;
}

}  // namespace raster_overflow_test
}  // namespace penumbra::test
