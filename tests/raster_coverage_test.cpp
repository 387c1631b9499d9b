// Watertightness of the top-left rule and the clipping paths: shared-edge fans and grid meshes cover every pixel
// centre of their union exactly once (checked on the reference's counts, on the kernels' output against the exact
// union, and by drawing two halves of a mesh separately), slivers, near-plane crossings and huge triangles that
// need the guard band, all compared exactly with the reference.
#include <gtest/gtest.h>

#include "host/views/raster_scene.h"
#include "raster/rasterizer.h"
#include "tests/raster_support.h"
#include "tests/support/cl_test.h"
#include "tools/selftest/reference/raster_ref.h"

namespace penumbra::test {
namespace raster_coverage_test {

class RasterCoverageTest : public ClTest {
 protected:
  RasterOutput draw(const Scene& scene, const RasterView& view) {
    Rasterizer raster(ctx());
    uploadScene(raster, scene);
    RasterOutput out = drawPoisoned(ctx(), raster, view);
    lastStats = raster.stats();
    return out;
  }
  RasterStats lastStats;
};

// The watertightness helpers (pixelView, samplesInside, coveredPixels, worstCoverage, halvesPartition, fanScene) are
// tools/selftest/reference/raster_compare.h's, which `penumbra selftest` runs too.
void expectSingleCoverage(const RefRasterizer& ref) {
  EXPECT_LE(worstCoverage(ref), 1) << "a pixel centre is covered by two triangles of a mesh";
}

// Draws the even and the odd triangles separately: the two coverages must be disjoint and add up to the whole.
void expectHalvesPartition(Context& ctx, const Scene& scene, const RasterView& view, const RasterOutput& whole) {
  const HalvesPartition p = halvesPartition(ctx, scene, view, whole);
  EXPECT_EQ(p.both, 0u) << "pixels covered by both halves";
  EXPECT_EQ(p.differ, 0u) << "pixels where the halves' union differs from the whole";
}

TEST_F(RasterCoverageTest, FanAroundPixelCentreCoversItsPolygonOnce) {
  // 48 spokes from a pixel centre; rim points on the 1/256 grid, several exactly on pixel centres.
  std::vector<glm::dvec2> rim;
  const Scene scene = fanScene({31.5f, 30.5f}, 24.0f, 48, rim);
  const RasterView view = pixelView(64, 64);
  const RasterOutput out = draw(scene, view);
  const RefRasterizer ref(scene, view);
  expectSingleCoverage(ref);
  EXPECT_TRUE(matchesReference(compareWithReference(out, ref, view, 1.0)));
  EXPECT_EQ(coveredPixels(out), samplesInside(rim, 64, 64));
  expectHalvesPartition(ctx(), scene, view, out);
}

TEST_F(RasterCoverageTest, SliverPinwheelHasNoCracks) {
  // 720 wedges a fraction of a pixel wide at the centre: slivers sharing every edge.
  std::vector<glm::dvec2> rim;
  const Scene scene = pinwheelScene(rim);
  const RasterView view = pixelView(128, 64);
  const RasterOutput out = draw(scene, view);
  const RefRasterizer ref(scene, view);
  expectSingleCoverage(ref);
  EXPECT_TRUE(matchesReference(compareWithReference(out, ref, view, 1.0)));
  EXPECT_EQ(coveredPixels(out), samplesInside(rim, 128, 64));
  expectHalvesPartition(ctx(), scene, view, out);
}

TEST_F(RasterCoverageTest, JitteredGridCoversItsRectangleOnce) {
  const Scene scene = gridScene(23, 17, {3.5f, 2.25f}, {93.5f, 60.75f}, 0.0f, 0.45f, 7);
  const RasterView view = pixelView(128, 64);
  const RasterOutput out = draw(scene, view);
  const RefRasterizer ref(scene, view);
  expectSingleCoverage(ref);
  EXPECT_TRUE(matchesReference(compareWithReference(out, ref, view, 1.0)));
  EXPECT_EQ(coveredPixels(out), samplesInside({{3.5, 2.25}, {93.5, 2.25}, {93.5, 60.75}, {3.5, 60.75}}, 128, 64));
  expectHalvesPartition(ctx(), scene, view, out);
}

TEST_F(RasterCoverageTest, PerspectiveGridMatchesAndPartitions) {
  Scene scene = gridScene(30, 30, {-3, -3}, {3, 3}, 0.0f, 0.3f, 11);
  for (glm::vec3& q : scene.positions) q = glm::vec3(q.x, 0.3f * std::sin(q.x + q.y), q.y);  // a wavy floor
  const RasterView view = perspectiveView(123, 77, {0.3f, 2.5f, 5.0f}, {0, 0, 0}, 55.0f, 0.5f, 30.0f);
  const RasterOutput out = draw(scene, view);
  const RefRasterizer ref(scene, view);
  expectSingleCoverage(ref);
  EXPECT_TRUE(matchesReference(compareWithReference(out, ref, view, 30.0), 4));
  expectHalvesPartition(ctx(), scene, view, out);
}

TEST_F(RasterCoverageTest, RandomSliversMatchReference) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1.5f, 1.5f), thin(-0.004f, 0.004f);
  std::vector<glm::vec3> p;
  std::vector<glm::uvec3> t;
  for (int i = 0; i < 400; ++i) {
    const glm::vec3 a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng));
    p.insert(p.end(), {a, b, 0.5f * (a + b) + glm::vec3(thin(rng), thin(rng), thin(rng))});
    t.emplace_back(3 * i, 3 * i + 1, 3 * i + 2);
  }
  const Scene scene = makeScene(p, t);
  const RasterView view = perspectiveView(150, 101, {0.2f, 0.4f, 5.0f}, {0, 0, 0}, 50.0f, 0.5f, 20.0f);
  const RasterOutput out = draw(scene, view);
  const RefRasterizer ref(scene, view);
  const RasterComparison cmp = compareWithReference(out, ref, view, 10.0);
  EXPECT_TRUE(matchesReference(cmp, cmp.covered / 100 + 2));
  EXPECT_GT(cmp.covered, 200u);
}

TEST_F(RasterCoverageTest, GroundPlaneThroughNearPlaneHasNoCracks) {
  // A floor that extends behind the camera: many triangles cross the near plane and are cut into two; the floor
  // covers everything below the horizon, with no crack along the cuts.
  const Scene floor = nearPlaneFloor();
  for (bool cull : {false, true}) {
    const RasterView view = nearPlaneFloorView(cull);
    const RasterOutput out = draw(floor, view);
    const RefRasterizer ref(floor, view);
    expectSingleCoverage(ref);
    EXPECT_TRUE(matchesReference(compareWithReference(out, ref, view, 100.0), 2));
    EXPECT_EQ(lastStats.trianglesSetUp, ref.drawnTriangles());
    for (int x = 0; x < view.width; ++x) EXPECT_NE(out.ids[x], kNoTriangle) << "bottom row, x " << x;
    if (!cull) expectHalvesPartition(ctx(), floor, view, out);
  }
}

TEST_F(RasterCoverageTest, TriangleBehindEyeIsClippedIntoTwo) {
  // One vertex behind the eye (w < 0), two in front: the near plane cuts a quad, drawn as two triangles.
  const Scene scene = makeScene({{-1, -0.5f, -3}, {1, -0.5f, -3}, {0, -0.5f, 4}}, {{0, 1, 2}});
  const RasterView view = perspectiveView(64, 48, {0, 0, 0}, {0, 0, -1}, 60.0f, 0.1f, 50.0f);
  const RasterOutput out = draw(scene, view);
  const RefRasterizer ref(scene, view);
  EXPECT_EQ(ref.drawnTriangles(), 2u);
  EXPECT_EQ(lastStats.trianglesSetUp, 2u);
  EXPECT_TRUE(matchesReference(compareWithReference(out, ref, view, 50.0)));
  EXPECT_GT(coveredPixels(out), 300u);
}

TEST_F(RasterCoverageTest, HugeTrianglesUseTheGuardBand) {
  // Vertices a million units out: far beyond the fixed-point range, so they are clipped to the guard band.
  const Scene scene = makeScene({{-1e6f, -1e6f, -1},
                                 {1e6f, -1e6f, -1},
                                 {0, 1e6f, -1},  // ortho: everywhere
                                 {-2e5f, -0.3f, 2e5f},
                                 {2e5f, -0.3f, 2e5f},
                                 {0, -0.3f, -2e5f}},  // a vast floor
                                {{0, 1, 2}, {3, 4, 5}});
  const RasterView persp = perspectiveView(90, 70, {0, 0.5f, 3}, {0, 0, 0}, 60.0f, 0.1f, 1e6f);
  const RasterView ortho = orthoView(70, 90, {0, 0, 3}, {0, 0, 0}, {-2, 2, -3, 3}, 0.5f, 10.0f);
  for (const RasterView& view : {persp, ortho}) {
    const RasterOutput out = draw(scene, view);
    const RefRasterizer ref(scene, view);
    EXPECT_TRUE(matchesReference(compareWithReference(out, ref, view, 10.0)));
    EXPECT_GE(ref.fannedTriangles(), 1u);  // the guard-band clip made polygons
  }
  // The orthographic view sees only the first triangle, and all of it.
  const RasterOutput out = draw(scene, ortho);
  for (size_t i = 0; i < out.ids.size(); ++i) ASSERT_EQ(out.ids[i], 0u) << i;
}

TEST_F(RasterCoverageTest, WidestViewportThroughAScissor) {
  // 8192 pixels across (64 bins, subpixel x up to 2^21), drawn through a scissor around the soup.
  const Scene scene = triangleSoup(400, 9, 1.5f, 0.5f);
  RasterView view = perspectiveView(8192, 300, {0, 0, 4.5f}, {0, 0, 0}, 50.0f, 0.5f, 20.0f);
  view.scissor = Scissor{3990, 0, 4203, 300};
  const RasterOutput out = draw(scene, view);
  const RefRasterizer ref(scene, view);
  const RasterComparison cmp = compareWithReference(out, ref, view, 10.0);
  EXPECT_TRUE(matchesReference(cmp, cmp.covered / 200 + 2));
  EXPECT_GT(cmp.covered, 3000u);
}

TEST_F(RasterCoverageTest, OneRowAndOneColumnViewports) {
  const Scene scene = triangleSoup(300, 10, 1.6f, 0.6f);
  for (auto [w, h] : {std::pair{509, 1}, std::pair{1, 263}}) {
    const RasterView view = perspectiveView(w, h, {0, 0, 4.5f}, {0, 0, 0}, 50.0f, 0.5f, 20.0f);
    const RasterOutput out = draw(scene, view);
    const RefRasterizer ref(scene, view);
    EXPECT_TRUE(matchesReference(compareWithReference(out, ref, view, 10.0), 2)) << w << "x" << h;
  }
}

}  // namespace raster_coverage_test
}  // namespace penumbra::test
