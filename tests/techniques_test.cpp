// End-to-end tests of the shadow techniques on PoCL, against analytic answers: a square occluder over a
// ground plane under a point light (the hard edge lands on the right pixels), planes that must stay fully
// lit (no acne, also at grazing light angles), and no NaN or out-of-range visibility on any built-in scene.
#include <gtest/gtest.h>

#include <cmath>

#include "host/pipeline/renderer.h"
#include "host/scene/procedural.h"
#include "host/techniques/technique.h"
#include "tests/support/cl_test.h"

namespace penumbra {
namespace {
using test::ClTest;

// A 10x10 ground at y = 0 and a 2x2 occluder at y = 2, both facing up.
Scene squareOverPlane() {
  Scene scene;
  auto quad = [&](float half, float y, uint32_t object) {
    const uint32_t base = static_cast<uint32_t>(scene.positions.size());
    for (glm::vec2 c : {glm::vec2(-1, -1), glm::vec2(1, -1), glm::vec2(1, 1), glm::vec2(-1, 1)}) {
      scene.positions.push_back({c.x * half, y, c.y * half});
      scene.normals.push_back({0, 1, 0});
    }
    scene.triangles.push_back({base, base + 2, base + 1});  // counter-clockwise seen from +Y
    scene.triangles.push_back({base, base + 3, base + 2});
    scene.objectIds.insert(scene.objectIds.end(), 2, object);
    scene.objectNames.push_back(object == 0 ? "ground" : "occluder");
  };
  quad(5.0f, 0.0f, 0);
  quad(1.0f, 2.0f, 1);
  return scene;
}

Camera topDown() {
  Camera camera;
  camera.eye = {0.0f, 7.0f, 5.0f};
  camera.target = {0.0f, 0.0f, 0.0f};
  camera.width = 160;
  camera.height = 120;
  return camera;
}

Light pointAbove() { return parseLight("spot:0,4,0:0,0,0:120"); }

RenderResult renderWith(Context& ctx, const Scene& scene, const Camera& camera, const Light& light,
                        const std::string& technique, std::map<std::string, std::string> values = {}) {
  const TechniqueInfo& info = findTechnique(technique);
  Params params(info.params);
  for (const auto& [name, value] : values) params.set(name, value);
  Renderer renderer(ctx, scene);
  return renderer.render(camera, light, info, params);
}

class Techniques : public ClTest, public ::testing::WithParamInterface<std::string> {};

TEST_P(Techniques, HardEdgeOfASquareOccluderLandsOnTheRightPixels) {
  // The light at y = 4 projects the occluder's edge |x| = 1 at y = 2 to |x| = 2 on the ground.
  RenderResult result =
      renderWith(ctx(), squareOverPlane(), topDown(), pointAbove(), GetParam(), {{"map-size", "1024"}});
  const Image& image = result.image;
  const auto &vis = image.require("visibility.Y").data, &px = image.require("P.X").data,
             &py = image.require("P.Y").data, &pz = image.require("P.Z").data, &a = image.require("A").data;
  constexpr float kEdgeBand = 0.08f;  // world units on the ground: ~6 texels of 0.014, covers filter widths and bias
  int shadowed = 0, lit = 0, wrong = 0;
  for (size_t i = 0; i < vis.size(); ++i) {
    if (a[i] == 0.0f || py[i] > 0.5f) continue;                            // background, or the occluder itself
    const float edge = std::max(std::abs(px[i]), std::abs(pz[i])) - 2.0f;  // < 0 inside the shadow
    if (std::abs(edge) < kEdgeBand) continue;
    const float expected = edge < 0 ? 0.0f : 1.0f;
    (expected == 0.0f ? shadowed : lit)++;
    if (std::abs(vis[i] - expected) > 1e-6f) ++wrong;
  }
  EXPECT_GT(shadowed, 2000);
  EXPECT_GT(lit, 5000);
  EXPECT_EQ(wrong, 0) << GetParam() << ": pixels away from the shadow edge with the wrong visibility";
}

TEST_P(Techniques, PlanesStayFullyLitAtAnyLightAngle) {
  const Scene plane = makeProcedural("plane");
  Camera camera = topDown();
  camera.eye = {0.0f, 6.0f, 6.0f};
  for (const char* light : {"dir:0,-1,0", "dir:1,-1,0.3", "dir:1,-0.18,0", "spot:3,2,1:0,0,0:150"}) {
    RenderResult result = renderWith(ctx(), plane, camera, parseLight(light), GetParam());
    const auto& vis = result.image.require("visibility.Y").data;
    size_t dark = 0;
    for (float v : vis) dark += v < 1.0f;
    EXPECT_EQ(dark, 0u) << GetParam() << " under " << light << ": acne on a plane that nothing shadows";
  }
}

TEST_P(Techniques, NoNanAndVisibilityInRangeOnEveryBuiltinScene) {
  for (const ProceduralInfo& info : proceduralScenes()) {
    const Scene scene = makeProcedural(info.name);
    Camera camera = scene.cameras.empty() ? topDown() : scene.cameras.front();
    camera.width = 96;
    camera.height = 64;
    ASSERT_FALSE(scene.lights.empty()) << info.name;
    RenderResult result = renderWith(ctx(), scene, camera, scene.lights.front(), GetParam(), {{"map-size", "512"}});
    for (const ImageChannel& channel : result.image.channels())
      for (float v : channel.data) ASSERT_FALSE(std::isnan(v)) << info.name << ": NaN in " << channel.name;
    for (float v : result.image.require("visibility.Y").data) {
      ASSERT_GE(v, 0.0f) << info.name;
      ASSERT_LE(v, 1.0f) << info.name;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(All, Techniques, ::testing::Values("sm", "pcf", "pcss"));

}  // namespace
}  // namespace penumbra
