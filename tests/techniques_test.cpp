// End-to-end tests of the shadow techniques on PoCL, against analytic answers: a square occluder over a
// ground plane under a point light (the hard edge lands on the right pixels), planes that must stay fully
// lit (no acne, also at grazing light angles), and no NaN or out-of-range visibility on any built-in scene.
#include <gtest/gtest.h>

#include <cmath>

#include "host/pipeline/renderer.h"
#include "host/scene/procedural.h"
#include "host/techniques/technique.h"
#include "tests/support/analytic_scenes.h"
#include "tests/support/cl_test.h"
#include "tests/support/render.h"

namespace penumbra {
namespace techniques_test {
using test::renderWith;
using test::ClTest;
using test::pointAbove;
using test::squareOverPlane;
using test::topDown;

// Away from the shadow's edge by `band` world units, visibility must be within `tolerance` of 0 or 1.
struct EdgeExpectation {
  float band, tolerance;
};
EdgeExpectation edgeExpectation(const std::string& technique) {
  // ~6 texels of 0.014 on the ground at map size 1024: covers the PCF/PCSS filter widths and the bias.
  if (technique == "sm" || technique == "pcf" || technique == "pcss" || technique == "fvsm") return {0.08f, 1e-6f};
  // izb is exact: only a pixel centre within rounding of the edge itself may land on either side.
  if (technique == "izb") return {1e-3f, 0.0f};
  // Moment techniques blur their moments (Gaussian taps reach 5 texels, plus the bilinear texel): 9 texels;
  // their umbra is only nearly 0 (Chebyshev with the minimum variance: ~1e-6; MSM's moment bias) and their
  // lit side nearly 1 where the Gaussian's far tail still sees the occluder.
  return {0.12f, 1e-3f};
}

class Techniques : public ClTest, public ::testing::WithParamInterface<std::string> {};

TEST_P(Techniques, HardEdgeOfASquareOccluderLandsOnTheRightPixels) {
  // The light at y = 4 projects the occluder's edge |x| = 1 at y = 2 to |x| = 2 on the ground.
  RenderResult result =
      renderWith(ctx(), squareOverPlane(), topDown(), pointAbove(), GetParam(), {{"map-size", "1024"}});
  const EdgeExpectation expect = edgeExpectation(GetParam());
  const test::HardEdgeCount count = test::checkHardEdge(result.image, expect.band, expect.tolerance);
  EXPECT_GT(count.shadowed, 2000);
  EXPECT_GT(count.lit, 5000);
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
