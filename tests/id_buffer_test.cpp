// The ID buffer (Luksch sec. 9.1) for sm, pcf, pssm and jittered on PoCL: with every bias at 0, flat and grazing
// receivers show no acne (the depth test does; pcf with object ids, as its taps leave the receiver's triangle);
// inter-object shadows keep their hard edge; the combined mode keeps the depth test within an object. Its side effects
// (shrunken shadows, no self-shadowing within one id) are measured in docs/techniques/jittered.md.
#include <gtest/gtest.h>

#include "host/pipeline/renderer.h"
#include "host/scene/procedural.h"
#include "tests/support/cl_test.h"
#include "tests/support/render.h"
#include "tools/selftest/reference/analytic_scenes.h"

namespace penumbra {
namespace id_buffer_test {
using test::ClTest;
using test::renderWith;

const test::Values kNoBias = {{"bias", "0"}, {"slope-bias", "0"}, {"normal-offset", "0"}, {"receiver-plane", "off"}};

size_t darkPixels(const RenderResult& r) {
  size_t dark = 0;
  for (float v : r.image.require("visibility.Y").data) dark += v < 1.0f;
  return dark;
}

class IdBuffer : public ClTest, public ::testing::WithParamInterface<std::string> {
 protected:
  test::Values technique(test::Values values) const {
    if (GetParam() == "pssm") values["pssm-filter"] = "hard", values.erase("receiver-plane");
    if (GetParam() == "pcf") values["pcf-adaptive"] = "off";
    return values;
  }
};

TEST_P(IdBuffer, NoAcneWithoutAnyBias) {
  const Scene plane = test::withSliverBelow(makeProcedural("plane"));  // a plane that may shadow
  Camera camera = test::topDown();
  camera.eye = {0.0f, 2.0f, 6.0f};
  camera.width = 128, camera.height = 96;
  size_t depthAcne = 0;
  for (const char* light : {"dir:0,-1,0", "dir:1,-1,0.3", "dir:1,-0.18,0", "dir:1,-0.05,0.2", "spot:3,2,1:0,0,0:150"}) {
    for (const char* mode : {"object", "polygon"}) {
      // PCF's taps reach texels beyond the receiver's own triangle: with polygon ids they see the plane's other
      // triangle and darken along the diagonal (the caveat in docs/techniques/jittered.md); object ids are the filtering mode.
      if (GetParam() == "pcf" && mode == std::string("polygon")) continue;
      test::Values values = technique(kNoBias);
      values["map-size"] = "512", values["id-buffer"] = mode;
      EXPECT_EQ(darkPixels(renderWith(ctx(), plane, camera, parseLight(light), GetParam(), values)), 0u)
          << mode << " under " << light;
    }
    test::Values depth = technique(kNoBias);
    depth["map-size"] = "512";
    depthAcne += darkPixels(renderWith(ctx(), plane, camera, parseLight(light), GetParam(), depth));
  }
  EXPECT_GT(depthAcne, 100u) << "the depth test without bias must show acne here, or this test shows nothing";
}

TEST_P(IdBuffer, InterObjectShadowsKeepTheirHardEdge) {
  for (const char* mode : {"object", "polygon", "combined"}) {
    if (GetParam() == "pcf" && mode == std::string("polygon")) continue;  // see NoAcneWithoutAnyBias
    test::Values values = technique(mode == std::string("combined") ? test::Values{} : kNoBias);
    values["map-size"] = "1024", values["id-buffer"] = mode;
    if (GetParam() == "pcf") values["pcf-radius"] = "1";
    const RenderResult r =
        renderWith(ctx(), test::squareOverPlane(), test::topDown(), test::pointAbove(), GetParam(), values);
    // The band of Techniques.HardEdge... (0.08, ~6 texels) holds the four-neighbour rule's shrink of one texel.
    const test::HardEdgeCount count = test::checkHardEdge(r.image, 0.08f, 1e-6f);
    EXPECT_GT(count.shadowed, 2000) << mode;
    EXPECT_GT(count.lit, 5000) << mode;
    EXPECT_EQ(count.wrong, 0) << mode;
  }
}

INSTANTIATE_TEST_SUITE_P(All, IdBuffer, ::testing::Values("sm", "pcf", "pssm", "jittered"));

}  // namespace id_buffer_test
}  // namespace penumbra
