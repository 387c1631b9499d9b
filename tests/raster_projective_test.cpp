// General projective light matrices (raster/rasterizer.h: any invertible matrix for linear view depth, as a LiSPSM
// warp needs): random soups against the reference rasterizer, the stored depth of a warped plane against the plane's
// own -z_eye at every pixel, and the refusals (other depth modes, the G-buffer, singular matrices).
#include <gtest/gtest.h>

#include "host/views/raster_scene.h"
#include "raster/rasterizer.h"
#include "tests/raster_support.h"
#include "tests/support/cl_test.h"
#include "tools/selftest/reference/raster_ref.h"

namespace penumbra::test {
namespace raster_projective_test {

class RasterProjectiveSoup : public ClTestWithParam<ProjectiveCase> {};

// The cases and the view are raster_compare.h's, which `penumbra selftest` draws too.
TEST_P(RasterProjectiveSoup, MatchesReference) {
  const ProjectiveCase& c = GetParam();
  const Scene scene = projectiveSoup(c);
  const RasterView view = projectiveView(c);
  Rasterizer raster(ctx());
  uploadScene(raster, scene);
  const RasterOutput out = drawPoisoned(ctx(), raster, view);
  const RefRasterizer ref(scene, view);
  const RasterComparison cmp = compareWithReference(out, ref, view, 10.0);
  EXPECT_GT(cmp.covered, projectiveMinCovered(c));
  EXPECT_TRUE(matchesReference(cmp, soupTiesAllowed(cmp.covered)));  // intersecting soups: rare legitimate ties
}

INSTANTIATE_TEST_SUITE_P(RasterProjectiveSoups, RasterProjectiveSoup, ::testing::ValuesIn(projectiveCases()),
                         [](const ::testing::TestParamInfo<ProjectiveCase>& param) { return param.param.name(); });

class RasterProjective : public ClTest {};

// Snapping moves a vertex by up to 1/512 pixel: under warpLike() at 83x71 that is <= 3.7e-4 eye units in x and
// 2.2e-4 in y (|d eye / d ndc| <= w / 0.5 and w^2 / 2.91 with w <= 3.4), i.e. <= 1.6e-4 of depth on the tilted plane
// below, whose depth is >= 3.5: 4.4e-5 relative. A plane of constant depth is immune to it.
constexpr double kSnapRel = 5e-5;

// Planes z = -5 + sx x + sy y (eye = world) under warpLike(): at every covered pixel centre, the eye (x, y) the pixel
// sees solves x_c - nx w_c = 0, y_c - ny w_c = 0 (x_c, y_c, w_c do not depend on z), and the stored depth must be the
// plane's -z there: the light's linear depth, not a warped one.
double worstPlaneDepthError(Context& ctx, float sx, float sy, size_t& covered) {
  auto planeZ = [&](double x, double y) { return -5.0 + sx * x + sy * y; };
  std::vector<glm::vec3> p;
  for (glm::vec2 q : {glm::vec2(-3, -2.5f), glm::vec2(3, -2.5f), glm::vec2(3, 3), glm::vec2(-3, 3)})
    p.emplace_back(q, static_cast<float>(planeZ(q.x, q.y)));
  const Scene scene = makeScene(p, {{0, 1, 2}, {0, 2, 3}});
  RasterView view;
  view.projection = warpLike();
  view.width = 83, view.height = 71, view.depthMode = DepthMode::kViewZ;
  Rasterizer raster(ctx);
  uploadScene(raster, scene);
  const RasterOutput out = drawPoisoned(ctx, raster, view);
  const glm::dmat4 P(view.projection);
  covered = 0;
  double worst = 0;
  for (int y = 0; y < view.height; ++y)
    for (int x = 0; x < view.width; ++x) {
      const size_t i = static_cast<size_t>(y) * view.width + x;
      if (out.ids[i] == kNoTriangle) continue;
      const double nx = (2.0 * x + 1) / view.width - 1, ny = (2.0 * y + 1) / view.height - 1;
      // row r: (P[0][r] - n P[0][3]) x + (P[1][r] - n P[1][3]) y = n P[3][3] - P[3][r]
      const double a = P[0][0] - nx * P[0][3], b = P[1][0] - nx * P[1][3], e = nx * P[3][3] - P[3][0];
      const double c = P[0][1] - ny * P[0][3], d = P[1][1] - ny * P[1][3], f = ny * P[3][3] - P[3][1];
      const double det = a * d - b * c, want = -planeZ((e * d - b * f) / det, (a * f - e * c) / det);
      ++covered;
      worst = std::max(worst, std::abs(out.depth[i] - want) / want);
    }
  return worst;
}

TEST_F(RasterProjective, WarpedPlaneStoresItsLinearDepth) {
  size_t covered = 0;
  const double flat = worstPlaneDepthError(ctx(), 0.0f, 0.0f, covered);
  EXPECT_GT(covered, 83u * 71u / 4);
  EXPECT_LE(flat, kViewZRel) << "constant depth 5: " << flat / kUlp << " ulp";
  const double tilted = worstPlaneDepthError(ctx(), 0.3f, -0.2f, covered);
  EXPECT_GT(covered, 83u * 71u / 4);
  EXPECT_LE(tilted, kViewZRel + kSnapRel) << "tilted plane: " << tilted / kUlp << " ulp";
}

TEST_F(RasterProjective, RefusesGeneralMatricesOutsideLinearDepthAndSingularOnes) {
  const Scene scene = triangleSoup(10, 3, 1.0f, 0.5f);
  Rasterizer raster(ctx());
  uploadScene(raster, scene);
  RasterTargets targets;
  RasterView view;
  view.view = glm::lookAt(glm::vec3(0, 0, 6), glm::vec3(0.0f), glm::vec3(0, 1, 0));
  view.projection = warpLike();
  view.width = view.height = 16;
  EXPECT_NO_THROW(raster.draw(view, targets));
  for (DepthMode mode : {DepthMode::kNdc, DepthMode::kDistance}) {
    view.depthMode = mode;
    EXPECT_THROW(raster.draw(view, targets), std::invalid_argument);
  }
  view.depthMode = DepthMode::kViewZ;
  GBuffer gbuffer;
  EXPECT_THROW(raster.drawGBuffer(view, gbuffer), std::invalid_argument);
  view.projection[0][0] = view.projection[1][0] = 0.0f;  // x_c = 0: singular
  EXPECT_THROW(raster.draw(view, targets), std::invalid_argument);
}

}  // namespace raster_projective_test
}  // namespace penumbra::test
