// End-to-end tests of the shadow techniques on PoCL, against analytic answers: a square occluder over a
// ground plane under a point light (the hard edge lands on the right pixels), planes that must stay fully
// lit (no acne, also at grazing light angles), and no NaN or out-of-range visibility on any built-in scene.
#include <gtest/gtest.h>

#include <cmath>

#include "host/pipeline/renderer.h"
#include "host/scene/procedural.h"
#include "host/techniques/technique.h"
#include "tests/support/cl_test.h"
#include "tests/support/render.h"
#include "tools/selftest/reference/analytic_scenes.h"

namespace penumbra {
namespace techniques_test {
using test::renderWith;
using test::ClTest;
using test::pointAbove;
using test::squareOverPlane;
using test::topDown;

class Techniques : public ClTest, public ::testing::WithParamInterface<std::string> {};

TEST_P(Techniques, HardEdgeOfASquareOccluderLandsOnTheRightPixels) {
  // The light at y = 4 projects the occluder's edge |x| = 1 at y = 2 to |x| = 2 on the ground.
  RenderResult result =
      renderWith(ctx(), squareOverPlane(), topDown(), pointAbove(), GetParam(), {{"map-size", "1024"}});
  const test::HardEdgeMargin margin = test::hardEdgeMargin(GetParam());
  const test::HardEdgeCount count = test::checkHardEdge(result.image, margin.band, margin.tolerance);
  EXPECT_GT(count.shadowed, test::kHardEdgeMinShadowed);
  EXPECT_GT(count.lit, test::kHardEdgeMinLit);
  EXPECT_EQ(count.wrong, 0) << GetParam() << ": pixels away from the shadow edge with the wrong visibility";
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
    ASSERT_TRUE(test::saneImage(result.image, info.name));
  }
}

INSTANTIATE_TEST_SUITE_P(All, Techniques,
                         ::testing::Values("sm", "pcf", "pcss", "vsm", "evsm2", "evsm4", "esm", "msm", "savsm",
                                           "lvsm", "jittered", "izb", "fvsm"));

}  // namespace techniques_test
}  // namespace penumbra
