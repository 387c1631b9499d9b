// The camera G-buffer: world position against the analytic ray-triangle hit computed in double, unit shading
// normals against the reference interpolation, facing sign, object ids, the same depth and ids as a depth-only
// draw, background and scissor rules; and a real model (Suzanne) through the whole pipeline.
#include <gtest/gtest.h>

#include <filesystem>

#include "host/scene/gltf_loader.h"
#include "host/views/raster_scene.h"
#include "raster/rasterizer.h"
#include "tests/raster_support.h"
#include "tests/support/cl_test.h"
#include "tools/selftest/reference/raster_ref.h"

namespace penumbra::test {
namespace raster_gbuffer_test {

// The comparison and its margins are tools/selftest/reference/raster_compare.h's (compareGBuffer), which `penumbra
// selftest` runs as well.
class RasterGBufferTest : public ClTest {
 protected:
  GBufferComparison check(const Scene& scene, const RasterView& view) {
    const GBufferComparison c = compareGBuffer(ctx(), scene, view);
    EXPECT_EQ(c.mismatches, 0u) << c.report;
    return c;
  }
};

TEST_F(RasterGBufferTest, PerspectiveSpheres) {
  const GBufferComparison r = check(twoSpheres(), gbufferPerspectiveView());
  EXPECT_GT(r.covered, kGBufferPerspectiveCovered);
  RecordProperty("worst_position_ulps", static_cast<int>(r.worstPositionUlps));
}

TEST_F(RasterGBufferTest, OrthographicSpheresWithScissorAndDistance) {
  EXPECT_GT(check(twoSpheres(), gbufferOrthoScissorView()).covered, kGBufferOrthoCovered);
}

TEST_F(RasterGBufferTest, BackFacesSeenThroughACutSphere) {
  // Half the triangles removed: the inside (back faces, facing sign -1) shows through.
  Scene s = sphereScene(12, 20, 1.0f, {0, 0, 0});
  std::vector<glm::uvec3> kept;
  for (const glm::uvec3& t : s.triangles)
    if (s.positions[t.x].z + s.positions[t.y].z + s.positions[t.z].z < 0.9f) kept.push_back(t);
  s.triangles = kept;
  s.objectIds.assign(kept.size(), 0);
  const RasterView view = perspectiveView(80, 80, {0.3f, 0.4f, 3.5f}, {0, 0, 0}, 45.0f, 0.5f, 10.0f);
  EXPECT_GT(check(s, view).covered, 1000u);
}

std::string findScene(const std::string& name) {
  for (const std::string& dir :
       {std::string(PENUMBRA_SCENES_DIR), std::string(PENUMBRA_SOURCE_DIR) + "/../shared/scenes"})
    if (std::filesystem::exists(dir + "/" + name)) return dir + "/" + name;
  return {};
}

TEST_F(RasterGBufferTest, SuzanneMatchesReference) {
  const std::string path = findScene("Suzanne.glb");
  if (path.empty()) GTEST_SKIP() << "Suzanne.glb not found in scenes/ or ../shared/scenes";
  const Scene scene = loadGltf(path);
  ASSERT_GT(scene.triangleCount(), 3000u);
  for (DepthMode mode : {DepthMode::kViewZ, DepthMode::kNdc}) {
    const RasterView view = perspectiveView(160, 120, {1.2f, 0.8f, 3.6f}, {0, 0, 0}, 45.0f, 0.5f, 20.0f, mode);
    Rasterizer raster(ctx());
    uploadScene(raster, scene);
    const RasterOutput out = drawPoisoned(ctx(), raster, view);
    const RefRasterizer ref(scene, view);
    const RasterComparison cmp = compareWithReference(out, ref, view, 10.0);
    EXPECT_TRUE(matchesReference(cmp, 4));
    EXPECT_GT(cmp.covered, 3000u);
  }
  const RasterView camera = perspectiveView(120, 100, {-1.5f, 0.5f, 3.0f}, {0, 0, 0}, 50.0f, 0.5f, 20.0f);
  EXPECT_GT(check(scene, camera).covered, 2000u);
}

}  // namespace raster_gbuffer_test
}  // namespace penumbra::test
