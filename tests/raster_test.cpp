// The binned rasterizer against the naive reference (tools/selftest/reference/raster_ref.cpp): exact coverage and depth
// within tolerance for random soups over viewport sizes that are not multiples of a tile (1x1, odd, prime),
// every depth mode, perspective and orthographic views, scissors, tile masks and back-face culling.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>
#include <set>
#include <span>
#include <vector>

#include "host/scene/procedural_mesh.h"
#include "host/views/raster_scene.h"
#include "raster/caster_test.h"
#include "raster/constants.h"
#include "raster/rasterizer.h"
#include "tests/raster_support.h"
#include "tests/support/cl_test.h"
#include "tools/selftest/reference/raster_ref.h"

namespace penumbra::test {
namespace raster_test {

class RasterTest : public ClTest {};

std::string soupName(const ::testing::TestParamInfo<SoupCase>& info) { return info.param.name(); }

class RasterSoupTest : public ClTestWithParam<SoupCase> {};

TEST_P(RasterSoupTest, MatchesReference) {
  const SoupCase& c = GetParam();
  const Scene scene = triangleSoup(c.triangles, 1234 + c.width, 1.8f, c.size);
  const RasterView view = soupView(c);
  Rasterizer raster(ctx());
  uploadScene(raster, scene);
  const RasterOutput out = drawPoisoned(ctx(), raster, view);
  const RefRasterizer ref(scene, view);
  const RasterComparison cmp = compareWithReference(out, ref, view, 10.0);
  // Random soups intersect: ties along intersection lines are legitimate, but rare.
  EXPECT_TRUE(matchesReference(cmp, soupTiesAllowed(cmp.covered)));
  EXPECT_EQ(raster.stats().trianglesIn, scene.triangleCount());
  EXPECT_EQ(raster.stats().retries, 0);
  RecordProperty("worst_depth_ulps", static_cast<int>(cmp.worstUlps));
}

INSTANTIATE_TEST_SUITE_P(RasterSoups, RasterSoupTest, ::testing::ValuesIn(soupCases()), soupName);

TEST_F(RasterTest, EmptySceneClearsToBackground) {
  Rasterizer raster(ctx());
  const RasterView view = perspectiveView(45, 31, {0, 0, 5}, {0, 0, 0}, 45.0f, 0.1f, 10.0f);
  const RasterOutput out = drawPoisoned(ctx(), raster, view);
  for (size_t i = 0; i < out.ids.size(); ++i) {
    ASSERT_EQ(out.ids[i], kNoTriangle) << i;
    ASSERT_TRUE(std::isinf(out.depth[i]) && out.depth[i] > 0) << i;
  }
}

TEST_F(RasterTest, ScissorLeavesOutsideUntouched) {
  const Scene scene = triangleSoup(300, 77, 1.8f, 0.6f);
  RasterView view = perspectiveView(150, 110, {0.5f, 1.0f, 6.0f}, {0, 0, 0}, 50.0f, 0.5f, 20.0f);
  view.scissor = Scissor{13, 21, 101, 90};  // not tile- or bin-aligned
  Rasterizer raster(ctx());
  uploadScene(raster, scene);
  const RasterOutput out = drawPoisoned(ctx(), raster, view);
  const RefRasterizer ref(scene, view);
  const RasterComparison cmp = compareWithReference(out, ref, view, 10.0);
  EXPECT_TRUE(matchesReference(cmp, cmp.covered / 200 + 2));
  EXPECT_GT(cmp.covered, 500u);
}

TEST_F(RasterTest, ScissorAcrossBinsAndOutsideViewport) {
  const Scene scene = triangleSoup(300, 78, 1.8f, 0.6f);
  RasterView view = perspectiveView(300, 280, {0.5f, 1.0f, 6.0f}, {0, 0, 0}, 50.0f, 0.5f, 20.0f);
  view.scissor = Scissor{120, 100, 400, 141};  // crosses a bin border, clamped on the right
  Rasterizer raster(ctx());
  uploadScene(raster, scene);
  const RasterOutput out = drawPoisoned(ctx(), raster, view);
  RasterView clamped = view;
  clamped.scissor = Scissor{120, 100, 300, 141};
  const RefRasterizer ref(scene, clamped);
  EXPECT_TRUE(matchesReference(compareWithReference(out, ref, clamped, 10.0), 20));
}

TEST_F(RasterTest, TileMaskDrawsItsTilesOnlyAndEqualsAFullDrawThere) {
  // A scattered mask (about one tile in three, a whole bin left out, the last partial row and column in) over a
  // viewport that is not tile-aligned, with and without a scissor: masked-in tiles equal the full draw bit for bit,
  // every other pixel keeps its poison.
  const Scene scene = triangleSoup(400, 91, 1.8f, 0.5f);
  for (const bool scissored : {false, true}) {
    RasterView view = perspectiveView(301, 203, {0.5f, 1.0f, 6.0f}, {0, 0, 0}, 50.0f, 0.5f, 20.0f);
    if (scissored) view.scissor = Scissor{13, 21, 290, 190};
    const int tilesX = (view.width + RASTER_TILE_SIZE - 1) / RASTER_TILE_SIZE;
    const int tilesY = (view.height + RASTER_TILE_SIZE - 1) / RASTER_TILE_SIZE;
    std::vector<uint32_t> mask(static_cast<size_t>(tilesX) * tilesY);
    for (int ty = 0; ty < tilesY; ++ty)
      for (int tx = 0; tx < tilesX; ++tx) {
        const bool firstBin = tx < RASTER_BIN_TILES && ty < RASTER_BIN_TILES;
        mask[ty * tilesX + tx] = !firstBin && ((tx * 7 + ty * 3) % 3 == 0 || tx == tilesX - 1 || ty == tilesY - 1);
      }
    Buffer<uint32_t> maskBuffer(ctx(), std::span<const uint32_t>(mask));
    Rasterizer raster(ctx());
    uploadScene(raster, scene);
    const RasterOutput full = drawPoisoned(ctx(), raster, view);
    RasterView masked = view;
    masked.tileMask = &maskBuffer;
    const RasterOutput part = drawPoisoned(ctx(), raster, masked);
    size_t drawn = 0, covered = 0;
    for (int y = 0; y < view.height; ++y)
      for (int x = 0; x < view.width; ++x) {
        const size_t i = static_cast<size_t>(y) * view.width + x;
        if (mask[(y / RASTER_TILE_SIZE) * tilesX + x / RASTER_TILE_SIZE] != 0) {
          ASSERT_EQ(part.ids[i], full.ids[i]) << x << "," << y;
          ASSERT_EQ(std::memcmp(&part.depth[i], &full.depth[i], sizeof(float)), 0) << x << "," << y;
          drawn += full.ids[i] != kPoisonId, covered += full.ids[i] != kPoisonId && full.ids[i] != kNoTriangle;
        } else {
          ASSERT_EQ(part.ids[i], kPoisonId) << x << "," << y;
          ASSERT_EQ(std::memcmp(&part.depth[i], &kPoison, sizeof(float)), 0) << x << "," << y;
        }
      }
    EXPECT_GT(drawn, 5000u) << scissored;
    EXPECT_GT(covered, 1000u) << scissored;
  }
  // A mask smaller than the tile grid, or one given to a G-buffer draw, is refused.
  RasterView view = perspectiveView(64, 64, {0, 0, 6}, {0, 0, 0}, 50.0f, 0.5f, 20.0f);
  Buffer<uint32_t> small(ctx(), 63);
  view.tileMask = &small;
  Rasterizer raster(ctx());
  uploadScene(raster, scene);
  RasterTargets targets;
  EXPECT_THROW(raster.draw(view, targets), std::invalid_argument);
  Buffer<uint32_t> enough(ctx(), 64);
  view.tileMask = &enough;
  GBuffer g;
  EXPECT_THROW(raster.drawGBuffer(view, g), std::invalid_argument);
}

TEST_F(RasterTest, EmptyScissorDrawsNothing) {
  const Scene scene = triangleSoup(20, 79, 1.0f, 1.0f);
  RasterView view = perspectiveView(40, 30, {0, 0, 6}, {0, 0, 0}, 50.0f, 0.5f, 20.0f);
  view.scissor = Scissor{10, 10, 10, 20};
  Rasterizer raster(ctx());
  uploadScene(raster, scene);
  const RasterOutput out = drawPoisoned(ctx(), raster, view);
  for (size_t i = 0; i < out.ids.size(); ++i) ASSERT_EQ(out.ids[i], kPoisonId);
}

// Fresh targets (allocated by the draw) are filled with the background only where the draw leaves pixels untouched:
// outside a scissor, in masked-out tiles, everywhere for an empty scissor; a draw over the whole viewport writes every
// pixel itself (the soups above check that against poisoned targets). The G-buffer likewise outside its scissor.
TEST_F(RasterTest, FreshTargetsHoldTheBackgroundWhereTheDrawLeavesThem) {
  const Scene scene = triangleSoup(200, 80, 1.8f, 0.6f);
  const RasterView whole = perspectiveView(77, 45, {0.5f, 1.0f, 6.0f}, {0, 0, 0}, 50.0f, 0.5f, 20.0f);
  Rasterizer raster(ctx());
  uploadScene(raster, scene);
  RasterTargets full;
  raster.draw(whole, full);
  const std::vector<uint32_t> fullIds = full.triangleId.download(ctx());
  const int tilesX = (whole.width + RASTER_TILE_SIZE - 1) / RASTER_TILE_SIZE;
  const int tilesY = (whole.height + RASTER_TILE_SIZE - 1) / RASTER_TILE_SIZE;
  std::vector<uint32_t> mask(static_cast<size_t>(tilesX) * tilesY, 0u);
  for (size_t t = 0; t < mask.size(); t += 2) mask[t] = 1u;
  Buffer<uint32_t> maskBuffer(ctx(), std::span<const uint32_t>(mask));
  struct Case {
    const char* what;
    std::optional<Scissor> scissor;
    const Buffer<uint32_t>* mask;
  };
  for (const Case& c :
       {Case{"scissor", Scissor{13, 9, 60, 40}, nullptr}, Case{"empty scissor", Scissor{5, 5, 5, 20}, nullptr},
        Case{"tile mask", std::nullopt, &maskBuffer}}) {
    RasterView view = whole;
    view.scissor = c.scissor;
    view.tileMask = c.mask;
    RasterTargets fresh;
    raster.draw(view, fresh);
    const std::vector<uint32_t> ids = fresh.triangleId.download(ctx());
    const std::vector<float> depth = fresh.depth.download(ctx());
    size_t drawn = 0, background = 0;
    for (int y = 0; y < view.height; ++y)
      for (int x = 0; x < view.width; ++x) {
        const size_t i = static_cast<size_t>(y) * view.width + x;
        const bool inScissor =
            !c.scissor || (x >= c.scissor->x0 && x < c.scissor->x1 && y >= c.scissor->y0 && y < c.scissor->y1);
        const bool inMask = c.mask == nullptr || mask[(y / RASTER_TILE_SIZE) * tilesX + x / RASTER_TILE_SIZE] != 0;
        if (inScissor && inMask) {
          ASSERT_EQ(ids[i], fullIds[i]) << c.what << " " << x << "," << y;
          ++drawn;
        } else {
          ASSERT_EQ(ids[i], kNoTriangle) << c.what << " " << x << "," << y;
          ASSERT_TRUE(std::isinf(depth[i]) && depth[i] > 0.0f) << c.what << " " << x << "," << y;
          ++background;
        }
      }
    EXPECT_GT(background, 500u) << c.what;
  }
  RasterView scissored = whole;
  scissored.scissor = Scissor{13, 9, 60, 40};
  GBuffer g;
  raster.drawGBuffer(scissored, g);
  const std::vector<cl_float4> position = g.position.download(ctx());
  const std::vector<uint32_t> objectId = g.objectId.download(ctx());
  size_t outside = 0;
  for (int y = 0; y < whole.height; ++y)
    for (int x = 0; x < whole.width; ++x) {
      if (x >= 13 && x < 60 && y >= 9 && y < 40) continue;
      const size_t i = static_cast<size_t>(y) * whole.width + x;
      ASSERT_EQ(position[i].s[3], 0.0f) << x << "," << y;
      ASSERT_EQ(objectId[i], kNoTriangle) << x << "," << y;
      ++outside;
    }
  EXPECT_GT(outside, 1000u);
}

// RasterTargets::keepEmptyTiles: targets drawn again and again keep a record of the tiles that hold only the
// background and skip rewriting them. Whatever the sequence of draws (the casters moving so that drawn tiles empty and
// empty ones fill, ids written or not, a scissor, a tile mask, another size and its transpose, a write from outside
// that is announced),
// the kept targets must hold exactly what a fresh draw leaves in the pixels it writes, and their earlier content
// elsewhere. On the CPU layout most tiles of these views are empty, and the record says so.
TEST_F(RasterTest, KeptEmptyTilesLeaveEveryDrawAsAFreshOne) {
  const Scene scene = triangleSoup(60, 91, 0.6f, 0.3f);  // a small cluster: most of each view's tiles stay empty
  Rasterizer raster(ctx());
  uploadScene(raster, scene);
  const int tilesX = (96 + RASTER_TILE_SIZE - 1) / RASTER_TILE_SIZE,
            tilesY = (80 + RASTER_TILE_SIZE - 1) / RASTER_TILE_SIZE;
  std::vector<uint32_t> mask(static_cast<size_t>(tilesX) * tilesY, 0u);
  for (size_t t = 0; t < mask.size(); t += 3) mask[t] = 1u;
  Buffer<uint32_t> maskBuffer(ctx(), std::span<const uint32_t>(mask));
  struct Step {
    const char* what;
    glm::vec3 target;  // where the view looks: the cluster moves across the frame
    int width, height;
    bool ids;
    std::optional<Scissor> scissor;
    const Buffer<uint32_t>* mask;
    bool foreignWrite;  // the depth filled with NaN from outside, then forgetEmptyTiles()
  };
  const std::optional<Scissor> none;
  const std::vector<Step> steps = {
      {"left", {1.5f, 0, 0}, 96, 80, true, none, nullptr, false},
      {"again", {1.5f, 0, 0}, 96, 80, true, none, nullptr, false},
      {"right", {-1.5f, 0, 0}, 96, 80, true, none, nullptr, false},
      {"centre, depth only", {0, 0.5f, 0}, 96, 80, false, none, nullptr, false},
      {"left, ids again", {1.5f, 0, 0}, 96, 80, true, none, nullptr, false},
      {"scissor", {-1.0f, -0.5f, 0}, 96, 80, true, Scissor{20, 13, 77, 60}, nullptr, false},
      {"tile mask", {0.5f, 1.0f, 0}, 96, 80, true, none, &maskBuffer, false},
      {"after the mask", {-1.5f, 0, 0}, 96, 80, true, none, nullptr, false},
      {"outside write", {1.5f, 0.5f, 0}, 96, 80, true, none, nullptr, true},
      {"another size", {0, 0, 0}, 120, 72, true, none, nullptr, false},
      {"back", {1.5f, 0, 0}, 120, 72, true, none, nullptr, false},
      {"transposed", {-1.5f, 0, 0}, 72, 120, true, none, nullptr, false},  // as many pixels and tiles, laid otherwise
  };
  RasterTargets kept;
  kept.keepEmptyTiles = true;
  std::vector<float> depth;  // what the kept targets must hold
  std::vector<uint32_t> ids;
  int lastWidth = 0, lastHeight = 0;
  size_t recordedEmpty = 0;
  for (const Step& step : steps) {
    RasterView view = perspectiveView(step.width, step.height, {0, 0, 6}, step.target, 60.0f, 0.5f, 20.0f);
    view.writeTriangleIds = step.ids;
    view.scissor = step.scissor;
    view.tileMask = step.mask;
    const size_t pixels = static_cast<size_t>(step.width) * step.height;
    if (step.width != lastWidth || step.height != lastHeight)  // reallocated: the background where nothing is drawn
      depth.assign(pixels, INFINITY), ids.assign(pixels, kNoTriangle);
    lastWidth = step.width, lastHeight = step.height;
    if (step.foreignWrite) {
      kept.depth.fill(ctx(), std::nanf(""));
      kept.forgetEmptyTiles();
      std::fill(depth.begin(), depth.end(), std::nanf(""));
    }
    raster.draw(view, kept);
    RasterTargets fresh;
    raster.draw(view, fresh);
    const std::vector<float> freshDepth = fresh.depth.download(ctx()), keptDepth = kept.depth.download(ctx());
    const std::vector<uint32_t> freshIds = step.ids ? fresh.triangleId.download(ctx()) : std::vector<uint32_t>{};
    const std::vector<uint32_t> keptIds = step.ids ? kept.triangleId.download(ctx()) : std::vector<uint32_t>{};
    size_t covered = 0;
    for (int y = 0; y < step.height; ++y)
      for (int x = 0; x < step.width; ++x) {
        const size_t i = static_cast<size_t>(y) * step.width + x;
        const bool inScissor = !step.scissor || (x >= step.scissor->x0 && x < step.scissor->x1 &&
                                                 y >= step.scissor->y0 && y < step.scissor->y1);
        const bool inMask = step.mask == nullptr || mask[(y / RASTER_TILE_SIZE) * tilesX + x / RASTER_TILE_SIZE] != 0;
        if (inScissor && inMask) {
          depth[i] = freshDepth[i];
          if (step.ids) ids[i] = freshIds[i];
        }
        ASSERT_EQ(std::memcmp(&keptDepth[i], &depth[i], sizeof(float)), 0)
            << step.what << " " << x << "," << y << ": " << keptDepth[i] << " against " << depth[i];
        if (step.ids) {
          ASSERT_EQ(keptIds[i], ids[i]) << step.what << " " << x << "," << y;
        }
        covered += std::isfinite(depth[i]);
      }
    EXPECT_GT(covered, 100u) << step.what;
    if (!kept.emptyTiles.empty() && kept.emptyTiles.size() > 1)
      for (uint32_t flag : kept.emptyTiles.download(ctx())) recordedEmpty += flag != 0u;
  }
  if (ctx().info().cpuLayouts()) {
    EXPECT_GT(recordedEmpty, 200u);  // the CPU layout keeps the record
  }
}

TEST_F(RasterTest, BackFaceCullingOnClosedMeshKeepsTheVisibleSurface) {
  const Scene sphere = sphereScene(12, 20, 1.2f, {0.1f, -0.2f, 0.0f});
  for (bool cull : {false, true}) {
    RasterView view = perspectiveView(96, 80, {0.5f, 1.5f, 4.0f}, {0, 0, 0}, 50.0f, 0.5f, 20.0f);
    view.cullBackFaces = cull;
    Rasterizer raster(ctx());
    uploadScene(raster, sphere);
    const RasterOutput out = drawPoisoned(ctx(), raster, view);
    const RefRasterizer ref(sphere, view);
    EXPECT_TRUE(matchesReference(compareWithReference(out, ref, view, 10.0))) << "cull " << cull;
    if (cull) {
      EXPECT_LT(raster.stats().trianglesSetUp, sphere.triangleCount() * 6 / 10);
    }
  }
}

TEST_F(RasterTest, BackFaceCullingDropsClockwiseTriangles) {
  // Two triangles side by side; the right one is wound clockwise as seen from the eye.
  const Scene scene = makeScene({{-1.5f, -1, 0}, {-0.5f, -1, 0}, {-1, 1, 0}, {0.5f, -1, 0}, {1, 1, 0}, {1.5f, -1, 0}},
                                {{0, 1, 2}, {3, 4, 5}});
  RasterView view = orthoView(40, 20, {0, 0, 5}, {0, 0, 0}, {-2, 2, -1, 1}, 1, 10);
  view.cullBackFaces = true;
  Rasterizer raster(ctx());
  uploadScene(raster, scene);
  const RasterOutput out = drawPoisoned(ctx(), raster, view);
  size_t left = 0, right = 0;
  for (uint32_t id : out.ids) left += id == 0, right += id == 1;
  EXPECT_GT(left, 50u);
  EXPECT_EQ(right, 0u);
  EXPECT_EQ(raster.stats().trianglesSetUp, 1u);
}

// RasterView::cullSolidsFarSides: boxes (one wound inside out) on an open ground quad, seen from a perspective eye and
// an orthographic direction, and from an eye inside a box (which keeps all its sides): the depth and the triangle ids
// are those of the draw without it, with fewer triangles set up; a general projection ignores it.
TEST_F(RasterTest, SolidsFarSidesAreLeftOutWithTheSameDepthAndIds) {
  Scene scene = makeScene({{-6, 0, -6}, {-6, 0, 6}, {6, 0, 6}, {6, 0, -6}}, {{0, 1, 2}, {0, 2, 3}});
  detail::addBox(scene, 0, {-2.0f, 0.0f, -1.0f}, {-0.5f, 1.5f, 0.5f});
  const size_t inverted = scene.triangles.size();
  detail::addBox(scene, 0, {1.0f, 0.2f, -2.0f}, {2.5f, 2.0f, -0.5f});
  for (size_t t = inverted; t < scene.triangles.size(); ++t) std::swap(scene.triangles[t].y, scene.triangles[t].z);
  detail::addBox(scene, 0, {-0.6f, 2.5f, 1.4f}, {0.6f, 3.7f, 2.6f});  // holds the third view's eye
  scene.objectIds.assign(scene.triangles.size(), 0);
  Rasterizer raster(ctx());
  uploadScene(raster, scene, findSolids(scene));
  struct Case {
    const char* name;
    RasterView view;
    bool fewer;  // some triangle faces away from the centre and is left out
  };
  RasterView general = perspectiveView(64, 48, {3, 6, 5}, {0, 0, 0}, 60.0f, 0.5f, 30.0f);
  general.projection[0][1] = 0.25f;
  const Case cases[] = {
      {"perspective", perspectiveView(120, 90, {3, 6, 5}, {0, 0, 0}, 60.0f, 0.5f, 30.0f), true},
      {"orthographic", orthoView(120, 90, {2, 8, 3}, {0, 0, 0}, {-6, 6, -5, 5}, 1.0f, 20.0f), true},
      {"eye inside a box", perspectiveView(96, 64, {0, 3, 2}, {0, 0, -3}, 120.0f, 0.05f, 30.0f), true},
      {"general", general, false},
  };
  for (const Case& c : cases) {
    RasterView view = c.view;
    view.cullSolidsFarSides = false;
    const RasterOutput both = drawPoisoned(ctx(), raster, view);
    const uint64_t all = raster.stats().trianglesSetUp;
    view.cullSolidsFarSides = true;
    const RasterOutput near = drawPoisoned(ctx(), raster, view);
    size_t differing = 0, covered = 0;
    for (size_t i = 0; i < both.depth.size(); ++i) {
      covered += both.ids[i] != kNoTriangle;
      differing += both.ids[i] != near.ids[i] || std::memcmp(&both.depth[i], &near.depth[i], sizeof(float)) != 0;
    }
    EXPECT_GT(covered, both.depth.size() / 4) << c.name;
    EXPECT_LE(differing, 2u) << c.name;  // a texel centre exactly on a silhouette edge may go to the other face
    if (c.fewer)
      EXPECT_LT(raster.stats().trianglesSetUp, all) << c.name;
    else
      EXPECT_EQ(raster.stats().trianglesSetUp, all) << c.name;
  }
}

// RasterView::casterLight (and Rasterizer::casterTest on the host): a ground quad under a box and a floating plate,
// drawn from above. Under a light above the ground (a ball, a sun's cone) the triangles in the ground's plane (the
// ground and the box's bottom) are left out and their texels stay empty, while every other texel keeps its depth and
// id; a light below the ground, a ball or a cone that the plane cuts, or geometry below the ground keeps every
// triangle. Conservative tile lists leave the same ones out. A degenerate light is refused.
// A ground (y = 0, 12 x 12) under a box and a tilted plate; the caster tests' scene, drawn from above.
Scene groundBoxPlate() {
  Scene scene = makeScene({{-6, 0, -6}, {-6, 0, 6}, {6, 0, 6}, {6, 0, -6}}, {{0, 1, 2}, {0, 2, 3}});
  detail::addBox(scene, 0, {-2.0f, 0.0f, -1.0f}, {-0.5f, 1.5f, 0.5f});
  detail::addTriangle(scene, 0, {0.5f, 2.0f, 0.5f}, {2.5f, 2.2f, 0.5f}, {1.5f, 2.1f, 2.5f});  // the plate
  scene.objectIds.assign(scene.triangles.size(), 0);
  return scene;
}
const RasterView kFromAbove = orthoView(96, 96, {0, 10, 0.01f}, {0, 0, 0}, {-7, 7, -7, 7}, 1.0f, 20.0f);

TEST_F(RasterTest, CasterTestLeavesOutOnlyWhatShadowsNoPointOfTheScene) {
  const Scene scene = groundBoxPlate();
  Scene below = scene;  // a sliver under the ground: the box of the scene then reaches under the ground's plane
  detail::addTriangle(below, 0, {3, -0.01f, 3}, {4, -0.01f, 3}, {3, -0.01f, 4});
  // The triangles lying in the plane y = h, which the caster test may leave out.
  auto inPlane = [](const Scene& s, uint32_t triangle, float h) {
    const glm::uvec3 t = s.triangles[triangle];
    return s.positions[t.x].y == h && s.positions[t.y].y == h && s.positions[t.z].y == h;
  };
  auto countInPlane = [&](const Scene& s, float h) {
    size_t n = 0;
    for (uint32_t t = 0; t < s.triangles.size(); ++t) n += inPlane(s, t, h);
    return n;
  };
  ASSERT_EQ(countInPlane(scene, 0.0f), 4u);  // the ground's 2 and the box's bottom 2
  ASSERT_EQ(countInPlane(below, -0.01f), 1u);
  auto ball = [](glm::vec3 centre, float radius) {
    RasterLight l;
    l.position = centre, l.radius = radius;
    return l;
  };
  auto cone = [](glm::vec3 towards, float degrees) {
    RasterLight l;
    l.directional = true, l.towards = glm::normalize(towards), l.angularRadius = glm::radians(degrees);
    return l;
  };
  struct Case {
    const char* name;
    const Scene* scene;
    RasterLight light;
    std::optional<float> plane;  // the plane whose triangles are left out; none: every triangle is drawn
  };
  const Case cases[] = {
      {"ball above", &scene, ball({1, 8, 2}, 0.5f), 0.0f},
      {"point above", &scene, ball({-4, 3, 5}, 0.0f), 0.0f},
      {"sun above", &scene, cone({0.3f, 1.0f, 0.2f}, 5.0f), 0.0f},
      {"ball below", &scene, ball({0, -5, 0}, 0.5f), std::nullopt},
      {"ball through the plane", &scene, ball({0, 0.3f, 0}, 0.5f), std::nullopt},
      {"sun grazing within its radius", &scene, cone({1.0f, std::tan(glm::radians(3.0f)), 0.0f}, 5.0f), std::nullopt},
      // The ground then shadows the sliver, which shadows nothing.
      {"geometry below the ground", &below, ball({1, 8, 2}, 0.5f), -0.01f},
  };
  const RasterView top = kFromAbove;
  for (const Case& c : cases) {
    Rasterizer raster(ctx());
    uploadScene(raster, *c.scene);
    RasterView view = top;
    const RasterOutput all = drawPoisoned(ctx(), raster, view);
    const uint64_t drawn = raster.stats().trianglesSetUp;
    view.casterLight = c.light;
    const RasterOutput casters = drawPoisoned(ctx(), raster, view);
    EXPECT_EQ(drawn - raster.stats().trianglesSetUp, c.plane ? countInPlane(*c.scene, *c.plane) : 0u) << c.name;
    const raster::CasterTest host = raster.casterTest(c.light);  // the host's double-precision test: the same ones
    for (uint32_t t = 0; t < c.scene->triangles.size(); ++t) {
      const glm::uvec3 v = c.scene->triangles[t];
      EXPECT_EQ(host.castsNothing(c.scene->positions[v.x], c.scene->positions[v.y], c.scene->positions[v.z]),
                c.plane && inPlane(*c.scene, t, *c.plane))
          << c.name << " triangle " << t;
    }
    size_t emptied = 0;
    for (size_t i = 0; i < all.depth.size(); ++i) {
      if (c.plane && all.ids[i] != kNoTriangle && inPlane(*c.scene, all.ids[i], *c.plane)) {
        ASSERT_EQ(casters.ids[i], kNoTriangle) << c.name << " " << i;
        ASSERT_EQ(casters.depth[i], std::numeric_limits<float>::infinity()) << c.name << " " << i;
        ++emptied;
      } else {
        ASSERT_EQ(casters.ids[i], all.ids[i]) << c.name << " " << i;
        ASSERT_EQ(std::memcmp(&casters.depth[i], &all.depth[i], sizeof(float)), 0) << c.name << " " << i;
      }
    }
    if (c.plane == 0.0f) {
      EXPECT_GT(emptied, all.depth.size() / 2) << c.name;  // the ground
    }
  }
  Rasterizer raster(ctx());
  uploadScene(raster, scene);
  RasterView view = top;
  // Conservative tile lists (izb's) leave the same triangles out of every tile.
  auto listedTriangles = [&](const RasterView& v) {
    const RasterTileLists lists = raster.drawTileLists(v);
    const std::vector<uint32_t> count = lists.count->download(ctx()), offset = lists.offset->download(ctx());
    const std::vector<uint32_t> entries = lists.entries->download(ctx());
    std::set<uint32_t> listed;
    for (int tile = 0; tile < lists.tilesX * lists.tilesY; ++tile)
      for (uint32_t e = offset[tile]; e < offset[tile] + count[tile]; ++e) listed.insert(entries[e]);
    return listed;
  };
  const std::set<uint32_t> all = listedTriangles(view);
  view.casterLight = ball({1, 8, 2}, 0.5f);
  const std::set<uint32_t> casters = listedTriangles(view);
  EXPECT_EQ(all.size(), scene.triangles.size());
  for (uint32_t t = 0; t < scene.triangles.size(); ++t)
    EXPECT_EQ(casters.count(t), inPlane(scene, t, 0.0f) ? 0u : 1u) << t;
  RasterTargets targets;
  view.casterLight = cone({0, 1, 0}, 90.0f);
  EXPECT_THROW(raster.draw(view, targets), std::invalid_argument);
  view.casterLight = ball({0, NAN, 0}, 1.0f);
  EXPECT_THROW(raster.draw(view, targets), std::invalid_argument);
}

// RasterView::recordCasterTiles: every triangle drawn, the same depths and ids as without a caster light, and a record
// per 8 x 8 tile that no tile holding a caster's texel is called caster-free, in both fine layouts alike; the ground's
// tiles away from the box and the plate are. A wrong tile index, a record of the last triangle only or one never
// cleared fails it.
TEST_F(RasterTest, CasterTilesDrawEverythingAndRecordTheTilesNoCasterReaches) {
  Scene scene = groundBoxPlate();
  ASSERT_TRUE(scene.materialIds.empty());
  std::rotate(scene.triangles.begin(), scene.triangles.begin() + 2, scene.triangles.end());  // the ground queued last
  RasterLight light;
  light.position = {1, 8, 2}, light.radius = 0.5f;
  const RasterView all = kFromAbove;
  RasterView view = all;
  view.casterLight = light;
  view.recordCasterTiles = true;
  const int tilesX = view.width / RASTER_TILE_SIZE, tilesY = view.height / RASTER_TILE_SIZE;
  auto record = [&](Context& ctx) {
    Rasterizer raster(ctx);
    uploadScene(raster, scene);
    const RasterOutput reference = drawPoisoned(ctx, raster, all);
    RasterTargets targets;
    targets.keepEmptyTiles = true;  // both records at once
    targets.casterFree.allocate(ctx, size_t(tilesX) * tilesY);
    targets.casterFree.fill(ctx, 7u);  // poisoned: every tile must be written
    raster.draw(view, targets);
    EXPECT_EQ(targets.depth.download(ctx), reference.depth);
    EXPECT_EQ(targets.triangleId.download(ctx), reference.ids);
    const Buffer<uint32_t>* tiles = targets.casterFreeTiles(view.width, view.height);
    EXPECT_EQ(targets.casterFreeTiles(view.width + 8, view.height), nullptr);
    EXPECT_NE(tiles, nullptr);
    std::vector<uint32_t> out = tiles != nullptr ? tiles->download(ctx) : std::vector<uint32_t>{};
    const raster::CasterTest host = raster.casterTest(light);
    int casterTiles = 0, freeTiles = 0;
    for (int ty = 0; ty < tilesY; ++ty)
      for (int tx = 0; tx < tilesX; ++tx) {
        bool caster = false;
        for (int y = 0; y < RASTER_TILE_SIZE; ++y)
          for (int x = 0; x < RASTER_TILE_SIZE; ++x) {
            const uint32_t id =
                reference.ids[size_t(ty * RASTER_TILE_SIZE + y) * view.width + tx * RASTER_TILE_SIZE + x];
            if (id == kNoTriangle) continue;
            const glm::uvec3 t = scene.triangles[id];
            caster |= !host.castsNothing(scene.positions[t.x], scene.positions[t.y], scene.positions[t.z]);
          }
        const uint32_t entry = out.empty() ? 7u : out[size_t(ty) * tilesX + tx];
        EXPECT_TRUE(entry == 0u || entry == 1u) << tx << "," << ty << ": " << entry;
        if (caster) {
          EXPECT_EQ(entry, 0u) << "tile " << tx << "," << ty << " holds a caster";
        }
        casterTiles += caster, freeTiles += entry == 1u;
      }
    EXPECT_GT(casterTiles, 4);
    EXPECT_GT(freeTiles, tilesX * tilesY / 2);  // the ground's
    EXPECT_LE(freeTiles, tilesX * tilesY - casterTiles);
    // A draw without the record forgets it.
    raster.draw(all, targets);
    EXPECT_EQ(targets.casterFreeTiles(view.width, view.height), nullptr);
    return out;
  };
  const std::vector<uint32_t> cpu = record(ctx());
  const std::unique_ptr<Context> gpu = smallGpuContext(ctx(), 16 * 1024);
  EXPECT_EQ(record(*gpu), cpu);  // the other fine layout where ctx() has the CPU one, and the same one elsewhere

  Rasterizer raster(ctx());
  uploadScene(raster, scene);
  RasterTargets targets;
  RasterView bad = view;
  bad.casterLight.reset();
  EXPECT_THROW(raster.draw(bad, targets), std::invalid_argument);  // nothing to tell casters by
  bad = view;
  bad.scissor = Scissor{0, 0, 8, 8};
  EXPECT_THROW(raster.draw(bad, targets), std::invalid_argument);  // not the whole viewport
}

// RasterView::receiverReach: RasterTargets::casterBox holds every tile a caster reaches, and a tile no caster reaches
// that lies beyond the reach of that box is the background while every other tile is drawn as without the reach, in
// both fine layouts alike; a later draw with every tile over the kept empty-tile record draws them again. A reach
// ignored (everything drawn), a box read as pixels instead of whole tiles or taken from the last record only, or a
// skipped tile recorded as empty that a later draw leaves alone fails it.
TEST_F(RasterTest, ReceiverReachLeavesTheReceiversBeyondItAsTheBackground) {
  Scene scene = groundBoxPlate();
  RasterLight light;
  light.position = {1, 8, 2}, light.radius = 0.5f;
  RasterView view = kFromAbove;
  view.casterLight = light;
  view.recordCasterTiles = true;
  const int tilesX = view.width / RASTER_TILE_SIZE, tilesY = view.height / RASTER_TILE_SIZE;
  constexpr int kReach = 5;  // pixels: less than a tile, so the tiles beyond are those a whole tile away
  auto draw = [&](Context& ctx) {
    Rasterizer raster(ctx);
    uploadScene(raster, scene);
    RasterTargets full;
    raster.draw(view, full);  // every tile (receiverReach -1)
    const std::vector<float> depth = full.depth.download(ctx);
    const std::vector<uint32_t> ids = full.triangleId.download(ctx);
    const std::vector<uint32_t> freeTiles = full.casterFree.download(ctx);
    const std::array<int, 4> box = full.casterBox;
    EXPECT_LT(box[0], box[2]);
    EXPECT_LT(box[1], box[3]);
    for (int k = 0; k < 4; ++k) EXPECT_EQ(box[k] % RASTER_TILE_SIZE, 0) << k;
    RasterTargets targets;
    targets.keepEmptyTiles = true;
    RasterView reach = view;
    reach.receiverReach = kReach;
    raster.draw(reach, targets);
    EXPECT_EQ(targets.casterBox, box);
    EXPECT_EQ(targets.casterFree.download(ctx), freeTiles);
    const std::vector<float> near = targets.depth.download(ctx);
    const std::vector<uint32_t> nearIds = targets.triangleId.download(ctx);
    int skipped = 0, drawnFree = 0;
    for (int ty = 0; ty < tilesY; ++ty)
      for (int tx = 0; tx < tilesX; ++tx) {
        const int x = tx * RASTER_TILE_SIZE, y = ty * RASTER_TILE_SIZE;
        const bool free = freeTiles[size_t(ty) * tilesX + tx] != 0u;
        if (!free) {
          EXPECT_TRUE(x >= box[0] && x + RASTER_TILE_SIZE <= box[2] && y >= box[1] && y + RASTER_TILE_SIZE <= box[3])
              << "caster tile " << tx << "," << ty << " outside the box";
        }
        const bool beyond = x + RASTER_TILE_SIZE <= box[0] - kReach || x >= box[2] + kReach ||
                            y + RASTER_TILE_SIZE <= box[1] - kReach || y >= box[3] + kReach;
        bool held = false;  // the full draw has a triangle in the tile
        for (int j = 0; j < RASTER_TILE_SIZE; ++j)
          for (int i = 0; i < RASTER_TILE_SIZE; ++i) {
            const size_t pixel = size_t(y + j) * view.width + x + i;
            held |= ids[pixel] != kNoTriangle;
            if (free && beyond) {
              EXPECT_EQ(near[pixel], std::numeric_limits<float>::infinity()) << tx << "," << ty;
              EXPECT_EQ(nearIds[pixel], kNoTriangle) << tx << "," << ty;
            } else {
              EXPECT_EQ(near[pixel], depth[pixel]) << tx << "," << ty;
              EXPECT_EQ(nearIds[pixel], ids[pixel]) << tx << "," << ty;
            }
          }
        skipped += free && beyond && held, drawnFree += free && !beyond && held;
      }
    EXPECT_GT(skipped, tilesX * tilesY / 4);  // the ground away from the box and the plate
    EXPECT_GT(drawnFree, 4);                  // the ground around them
    raster.draw(view, targets);               // every tile again, over the empty-tile record
    EXPECT_EQ(targets.depth.download(ctx), depth);
    EXPECT_EQ(targets.triangleId.download(ctx), ids);
    return near;
  };
  const std::vector<float> cpu = draw(ctx());
  const std::unique_ptr<Context> gpu = smallGpuContext(ctx(), 16 * 1024);
  EXPECT_EQ(draw(*gpu), cpu);

  Rasterizer raster(ctx());
  uploadScene(raster, scene);
  RasterTargets targets;
  RasterView bad = view;
  bad.recordCasterTiles = false;
  bad.receiverReach = 0;
  EXPECT_THROW(raster.draw(bad, targets), std::invalid_argument);  // no caster tiles to reach from
}

// RasterView::writeTriangleIds false: the same depths, and the id target left as it was (poisoned ids stay; fresh
// targets get one unused entry).
TEST_F(RasterTest, DepthOnlyDrawsLeaveTheIdsAlone) {
  const Scene soup = triangleSoup(300, 11, 2.0f, 0.6f);
  RasterView view = perspectiveView(77, 53, {0.5f, 1.0f, 6.0f}, {0, 0, 0}, 50.0f, 0.5f, 20.0f);
  Rasterizer raster(ctx());
  uploadScene(raster, soup);
  const RasterOutput both = drawPoisoned(ctx(), raster, view);
  view.writeTriangleIds = false;
  const RasterOutput depthOnly = drawPoisoned(ctx(), raster, view);
  size_t covered = 0;
  for (size_t i = 0; i < both.depth.size(); ++i) {
    covered += both.ids[i] != kNoTriangle;
    ASSERT_EQ(std::memcmp(&both.depth[i], &depthOnly.depth[i], sizeof(float)), 0) << i;
    ASSERT_EQ(depthOnly.ids[i], kPoisonId) << i;
  }
  EXPECT_GT(covered, both.depth.size() / 4);
  RasterTargets fresh;
  raster.draw(view, fresh);
  EXPECT_EQ(fresh.triangleId.size(), 1u);
  EXPECT_EQ(fresh.depth.download(ctx()), both.depth);
}

TEST_F(RasterTest, RejectsUnsupportedViews) {
  Rasterizer raster(ctx());
  RasterTargets targets;
  RasterView view = perspectiveView(16, 16, {0, 0, 5}, {0, 0, 0}, 45.0f, 0.1f, 10.0f);
  view.width = 0;
  EXPECT_THROW(raster.draw(view, targets), std::invalid_argument);
  view.width = RASTER_MAX_VIEWPORT + 1;
  EXPECT_THROW(raster.draw(view, targets), std::invalid_argument);
  view.width = 16;
  view.projection[0][1] = 0.5f;  // skewed: general, supported for linear view depth only (raster_projective_test)
  view.depthMode = DepthMode::kNdc;
  EXPECT_THROW(raster.draw(view, targets), std::invalid_argument);
  view.depthMode = DepthMode::kViewZ;
  view.projection = glm::mat4(1.0f);
  view.projection[3][3] = std::nanf("");
  EXPECT_THROW(raster.draw(view, targets), std::invalid_argument);
}

TEST_F(RasterTest, DeterministicAcrossRuns) {
  // Overlapping coplanar triangles: depth ties everywhere, decided by float rounding and the id tie-break, the
  // same way every time whatever order the queues were filled in.
  Scene scene = triangleSoup(500, 5, 1.5f, 0.8f);
  for (glm::vec3& p : scene.positions) p.z = 0.0f;
  const RasterView view = orthoView(97, 61, {0, 0, 5}, {0, 0, 0}, {-2, 2, -1.5f, 1.5f}, 1, 10);
  Rasterizer raster(ctx());
  uploadScene(raster, scene);
  const RasterOutput a = drawPoisoned(ctx(), raster, view), b = drawPoisoned(ctx(), raster, view);
  EXPECT_EQ(a.ids, b.ids);
  EXPECT_EQ(a.depth, b.depth);
  const RefRasterizer ref(scene, view);
  const RasterComparison cmp = compareWithReference(a, ref, view, 10.0);
  EXPECT_TRUE(matchesReference(cmp, cmp.covered));
}

}  // namespace raster_test
}  // namespace penumbra::test
