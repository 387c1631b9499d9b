// The camera G-buffer: world position against the analytic ray-triangle hit computed in double, unit shading
// normals against the reference interpolation, facing sign, object ids, the same depth and ids as a depth-only
// draw, background and scissor rules; and a real model (Suzanne) through the whole pipeline.
#include <filesystem>

#include <gtest/gtest.h>

#include "host/scene/gltf_loader.h"
#include "raster/rasterizer.h"
#include "tests/raster_support.h"
#include "tests/reference/raster_ref.h"
#include "tests/support/cl_test.h"
#include "host/views/raster_scene.h"

namespace penumbra::test {
namespace raster_gbuffer_test {

// Float ray-plane intersection (raster/gbuffer.cl): error <= kPositionUlps ulp of (|eye| + |hit|) / |cos|, where
// cos is between the ray and the plane normal; measured worst about 2.
constexpr double kPositionUlps = 16;
constexpr double kUnitLength = 1e-5;   // |normal| - 1: one float normalisation
constexpr double kNormalError = 2e-4;  // interpolated normal vs double: float barycentrics of a float hit
constexpr double kMinCos = 0.05;       // grazing pixels skip the normal check: barycentrics there amplify error

class RasterGBufferTest : public ClTest {
 protected:
  struct Result {
    size_t covered = 0;
    double worstPositionUlps = 0;
  };
  Result check(const Scene& scene, const RasterView& view);
};

// Allocates the G-buffer and fills it with poison, so that pixels the kernels never write show up.
GBuffer poisonedGBuffer(Context& ctx, int width, int height) {
  GBuffer g;
  const size_t n = static_cast<size_t>(width) * height;
  g.width = width, g.height = height;
  g.depth.allocate(ctx, n), g.depth.fill(ctx, kPoison);
  g.triangleId.allocate(ctx, n), g.triangleId.fill(ctx, kPoisonId);
  g.objectId.allocate(ctx, n), g.objectId.fill(ctx, kPoisonId);
  g.position.allocate(ctx, n), g.position.fill(ctx, cl_float4{{kPoison, kPoison, kPoison, kPoison}});
  g.normal.allocate(ctx, n), g.normal.fill(ctx, cl_float4{{kPoison, kPoison, kPoison, kPoison}});
  return g;
}

RasterGBufferTest::Result RasterGBufferTest::check(const Scene& scene, const RasterView& view) {
  Rasterizer raster(ctx());
  uploadScene(raster, scene);
  GBuffer g = poisonedGBuffer(ctx(), view.width, view.height);
  raster.drawGBuffer(view, g);
  const RasterOutput depthOnly = drawPoisoned(ctx(), raster, view);
  const std::vector<uint32_t> ids = g.triangleId.download(ctx()), objects = g.objectId.download(ctx());
  const std::vector<float> depth = g.depth.download(ctx());
  const std::vector<cl_float4> pos = g.position.download(ctx()), nrm = g.normal.download(ctx());
  EXPECT_EQ(ids, depthOnly.ids);
  EXPECT_EQ(depth, depthOnly.depth);
  const glm::dmat4 toWorld = glm::inverse(glm::dmat4(view.projection) * glm::dmat4(view.view));
  const glm::dvec3 eye = glm::inverse(glm::dmat4(view.view))[3];
  const Scissor s = view.scissor.value_or(Scissor{0, 0, view.width, view.height});
  Result result;
  for (int y = 0; y < view.height; ++y)
    for (int x = 0; x < view.width; ++x) {
      const size_t i = static_cast<size_t>(y) * view.width + x;
      const glm::dvec4 p(pos[i].s[0], pos[i].s[1], pos[i].s[2], pos[i].s[3]);
      const glm::dvec4 n(nrm[i].s[0], nrm[i].s[1], nrm[i].s[2], nrm[i].s[3]);
      if (x < s.x0 || x >= s.x1 || y < s.y0 || y >= s.y1) {
        EXPECT_TRUE(p.x == kPoison && n.w == kPoison && objects[i] == kPoisonId) << x << "," << y;
        continue;
      }
      if (ids[i] == kNoTriangle) {
        EXPECT_TRUE(p == glm::dvec4(0) && n == glm::dvec4(0) && objects[i] == kNoTriangle) << x << "," << y;
        continue;
      }
      ++result.covered;
      if (ids[i] >= scene.triangles.size()) {
        ADD_FAILURE() << x << "," << y << ": triangle id " << ids[i];
        return result;
      }
      EXPECT_EQ(objects[i], scene.objectIds[ids[i]]);
      // The analytic hit of the pixel-centre ray with the triangle's plane, in double.
      const double xn = (2.0 * x + 1) / view.width - 1, yn = (2.0 * y + 1) / view.height - 1;
      glm::dvec4 a = toWorld * glm::dvec4(xn, yn, -1, 1), b = toWorld * glm::dvec4(xn, yn, 1, 1);
      a /= a.w, b /= b.w;
      const glm::dvec3 dir = glm::normalize(glm::dvec3(b - a));
      const glm::uvec3 tri = scene.triangles[ids[i]];
      const glm::dvec3 p0 = scene.positions[tri.x], p1 = scene.positions[tri.y], p2 = scene.positions[tri.z];
      const glm::dvec3 normal = glm::cross(p1 - p0, p2 - p0);
      const double cosine = std::abs(glm::dot(glm::normalize(normal), dir));
      const glm::dvec3 hit = glm::dvec3(a) + glm::dot(normal, p0 - glm::dvec3(a)) / glm::dot(normal, dir) * dir;
      const double scale = (glm::length(eye) + glm::length(hit)) / std::max(cosine, 1e-3) * kUlp;
      const double ulps = glm::length(glm::dvec3(p) - hit) / scale;
      result.worstPositionUlps = std::max(result.worstPositionUlps, ulps);
      EXPECT_LE(ulps, kPositionUlps) << x << "," << y << " triangle " << ids[i];
      EXPECT_EQ(p.w, 1.0);
      EXPECT_NEAR(glm::length(glm::dvec3(n)), 1.0, kUnitLength) << x << "," << y;
      EXPECT_EQ(n.w, glm::dot(normal, dir) < 0 ? 1.0 : -1.0) << x << "," << y;
      if (cosine < kMinCos) continue;
      glm::dvec3 w(glm::dot(normal, glm::cross(p1 - hit, p2 - hit)), glm::dot(normal, glm::cross(p2 - hit, p0 - hit)),
                   0);
      w /= glm::dot(normal, normal);
      w.z = 1 - w.x - w.y;
      w = glm::max(w, 0.0) / (glm::max(w, 0.0).x + glm::max(w, 0.0).y + glm::max(w, 0.0).z);
      const glm::dvec3 expected =
          glm::normalize(w.x * glm::dvec3(scene.normals[tri.x]) + w.y * glm::dvec3(scene.normals[tri.y]) +
                         w.z * glm::dvec3(scene.normals[tri.z]));
      EXPECT_LE(glm::length(glm::dvec3(n) - expected), kNormalError) << x << "," << y;
    }
  return result;
}

Scene twoSpheres() {
  Scene a = sphereScene(14, 24, 1.0f, {-0.6f, 0.1f, 0.0f}), b = sphereScene(10, 16, 0.7f, {0.9f, -0.2f, 0.8f});
  const uint32_t offset = static_cast<uint32_t>(a.positions.size());
  a.positions.insert(a.positions.end(), b.positions.begin(), b.positions.end());
  a.normals.insert(a.normals.end(), b.normals.begin(), b.normals.end());
  for (const glm::uvec3& t : b.triangles) a.triangles.push_back(t + offset);
  a.objectIds.resize(a.triangles.size(), 1);
  a.objectNames.push_back("second");
  return a;
}

TEST_F(RasterGBufferTest, PerspectiveSpheres) {
  const RasterView view = perspectiveView(113, 87, {0.8f, 1.6f, 4.5f}, {0, 0, 0}, 45.0f, 0.5f, 30.0f);
  const Result r = check(twoSpheres(), view);
  EXPECT_GT(r.covered, 2000u);
  RecordProperty("worst_position_ulps", static_cast<int>(r.worstPositionUlps));
}

TEST_F(RasterGBufferTest, OrthographicSpheresWithScissorAndDistance) {
  RasterView view =
      orthoView(90, 70, {-3, 2, 4}, {0, 0, 0}, {-2.2f, 2.2f, -1.7f, 1.7f}, 0.5f, 15.0f, DepthMode::kDistance);
  view.scissor = Scissor{7, 5, 83, 61};
  EXPECT_GT(check(twoSpheres(), view).covered, 1500u);
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
