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

// World = window pixels: for power-of-two sizes x_win = x exactly for dyadic x, so snapping is exact and tests can
// place vertices on pixel centres (i + 0.5) and edges through them.
RasterView pixelView(int w, int h) {
  RasterView v;
  v.projection = glm::ortho(0.0f, float(w), 0.0f, float(h), -1.0f, 1.0f);
  v.width = w, v.height = h;
  return v;
}

// Pixel centres inside a convex counter-clockwise polygon of exactly representable window positions, with the same
// top-left rule: the set a watertight fan or mesh over that polygon must cover exactly once.
size_t samplesInside(const std::vector<glm::dvec2>& polygon, int w, int h) {
  size_t count = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      bool inside = true;
      for (size_t k = 0; k < polygon.size() && inside; ++k) {
        const glm::dvec2 a = polygon[k] * 256.0, b = polygon[(k + 1) % polygon.size()] * 256.0;
        const double e = (b.x - a.x) * (y * 256.0 + 128 - a.y) - (b.y - a.y) * (x * 256.0 + 128 - a.x);
        const bool owned = b.y < a.y || (b.y == a.y && b.x < a.x);
        inside = e > 0 || (e == 0 && owned);
      }
      count += inside;
    }
  return count;
}

size_t coveredPixels(const RasterOutput& out) {
  size_t n = 0;
  for (uint32_t id : out.ids) n += id != kNoTriangle;
  return n;
}

void expectSingleCoverage(const RefRasterizer& ref) {
  int worst = 0;
  for (int c : ref.result().coverage) worst = std::max(worst, c);
  EXPECT_LE(worst, 1) << "a pixel centre is covered by two triangles of a mesh";
}

// Draws the even and the odd triangles separately: the two coverages must be disjoint and add up to the whole.
void expectHalvesPartition(Context& ctx, const Scene& scene, const RasterView& view, const RasterOutput& whole) {
  Scene halves[2] = {scene, scene};
  for (int h = 0; h < 2; ++h) {
    halves[h].triangles.clear();
    halves[h].objectIds.clear();
    for (size_t t = h; t < scene.triangles.size(); t += 2) halves[h].triangles.push_back(scene.triangles[t]);
    halves[h].objectIds.assign(halves[h].triangles.size(), 0);
  }
  Rasterizer raster(ctx);
  uploadScene(raster, halves[0]);
  const RasterOutput even = drawPoisoned(ctx, raster, view);
  uploadScene(raster, halves[1]);
  const RasterOutput odd = drawPoisoned(ctx, raster, view);
  size_t both = 0, differ = 0;
  for (size_t i = 0; i < whole.ids.size(); ++i) {
    const bool a = even.ids[i] != kNoTriangle, b = odd.ids[i] != kNoTriangle;
    both += a && b;
    differ += (a || b) != (whole.ids[i] != kNoTriangle);
  }
  EXPECT_EQ(both, 0u) << "pixels covered by both halves";
  EXPECT_EQ(differ, 0u) << "pixels where the halves' union differs from the whole";
}

TEST_F(RasterCoverageTest, FanAroundPixelCentreCoversItsPolygonOnce) {
  // 48 spokes from a pixel centre; rim points on the 1/256 grid, several exactly on pixel centres.
  const glm::vec2 c(31.5f, 30.5f);
  std::vector<glm::vec3> p{{c, 0}};
  std::vector<glm::dvec2> rim;
  const int spokes = 48;
  for (int k = 0; k < spokes; ++k) {
    const float a = 2 * glm::pi<float>() * k / spokes;
    const glm::vec2 q = glm::round((c + 24.0f * glm::vec2(std::cos(a), std::sin(a))) * 256.0f) / 256.0f;
    p.emplace_back(q, 0);
    rim.emplace_back(q);
  }
  std::vector<glm::uvec3> t;
  for (int k = 0; k < spokes; ++k) t.emplace_back(0, 1 + k, 1 + (k + 1) % spokes);
  const Scene scene = makeScene(p, t);
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
  const glm::vec2 c(40.0f + 37 / 256.0f, 33.0f + 91 / 256.0f);
  std::vector<glm::vec3> p{{c, 0}};
  std::vector<glm::dvec2> rim;
  const int spokes = 720;
  for (int k = 0; k < spokes; ++k) {
    const float a = 2 * glm::pi<float>() * k / spokes;
    const glm::vec2 q = glm::round((c + 30.0f * glm::vec2(std::cos(a), std::sin(a))) * 256.0f) / 256.0f;
    p.emplace_back(q, 0);
    rim.emplace_back(q);
  }
  std::vector<glm::uvec3> t;
  for (int k = 0; k < spokes; ++k) t.emplace_back(0, 1 + k, 1 + (k + 1) % spokes);
  const Scene scene = makeScene(p, t);
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
  const Scene scene = gridScene(24, 24, {-60, -60}, {60, 60}, 0.0f, 0.0f, 1);
  Scene floor = scene;
  for (glm::vec3& q : floor.positions) q = glm::vec3(q.x, 0.0f, -q.y);  // counter-clockwise seen from above
  for (bool cull : {false, true}) {
    RasterView view = perspectiveView(101, 67, {0.3f, 1.0f, 0.2f}, {0.5f, 0.6f, -5.0f}, 70.0f, 0.25f, 100.0f);
    view.cullBackFaces = cull;
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
