// Several lights in one frame: each light's layer equals the single-light render of that light bit for bit, the
// preview sums the lights' direct terms over one ambient term, the reference traces every light into the same
// layers, each light may have its own technique, same-named lights get distinct layers, and a point light among them
// (six cube faces) gets its layer like any other.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "host/eval/metrics.h"
#include "host/pipeline/renderer.h"
#include "host/scene/light_names.h"
#include "host/techniques/registry.h"
#include "scene_test_util.h"
#include "tests/support/cl_test.h"
#include "tools/reference/reference.h"
#include "tools/selftest/reference/analytic_scenes.h"

namespace penumbra {
namespace multilight_test {

// kernels/shade.cl's constants: the ambient term a multi-light preview adds once and each single-light one adds.
constexpr float kAlbedo = 0.75f, kAmbient = 0.12f;
constexpr float kSumTolerance = 2e-6f;  // float round-off of (a + s) + (b + s) against a + b + s on values below 2

// A hard spot and a hard sun over the square: two shadows in different places.
std::vector<Light> spotAndSun() {
  Light key = parseLight("spot:0,4,0:0,0,0:120");
  key.name = "Key";
  Light sun = parseLight("dir:0.5,-1,0.2");
  sun.name = "Sun";
  return {key, sun};
}

std::vector<FrameLight> withTechnique(const std::vector<Light>& lights, const std::string& technique) {
  const TechniqueInfo& info = findTechnique(technique);
  std::vector<FrameLight> out;
  for (const Light& light : lights) out.push_back({light, &info, Params(info.params)});
  return out;
}

RenderResult renderOne(Context& ctx, const Scene& scene, const Light& light, const std::string& technique) {
  Renderer renderer(ctx, scene);
  return renderer.render(test::topDown(), withTechnique({light}, technique));
}

class MultiLight : public test::ClTest {};

TEST_F(MultiLight, EachLayerIsTheSingleLightRenderBitForBit) {
  const Scene scene = test::squareOverPlane();
  const std::vector<Light> lights = spotAndSun();
  Renderer renderer(ctx(), scene);
  const Image both = renderer.render(test::topDown(), withTechnique(lights, "pcf")).image;
  const Image again = renderer.render(test::topDown(), withTechnique(lights, "pcf")).image;  // steady state
  for (const Light& light : lights) {
    const Image alone = renderOne(ctx(), scene, light, "pcf").image;
    const std::string layer = lightChannel("visibility", light.name);
    EXPECT_EQ(both.require(layer).data, alone.require("visibility.Y").data) << light.name;
    EXPECT_EQ(again.require(layer).data, alone.require(layer).data) << light.name;
  }
  EXPECT_EQ(both.require("visibility.Y").data, both.require("visibility.Key.Y").data);
  EXPECT_NE(both.require("visibility.Key.Y").data, both.require("visibility.Sun.Y").data);
  EXPECT_EQ(both.attributes().at("penumbra:light-name"), "Key");
  EXPECT_NE(both.attributes().at("penumbra:lights").find("Sun=dir:"), std::string::npos);
}

TEST_F(MultiLight, OneLightKeepsItsPreviewAndAddsItsLayer) {
  const Scene scene = test::squareOverPlane();
  const Light light = test::pointAbove();  // unnamed: the layer "light"
  Renderer renderer(ctx(), scene);
  const TechniqueInfo& info = findTechnique("sm");
  const Image image = renderer.render(test::topDown(), light, info, Params(info.params)).image;
  EXPECT_EQ(image.require("visibility.light.Y").data, image.require("visibility.Y").data);
  EXPECT_EQ(image.attributes().count("penumbra:lights"), 0u);
}

TEST_F(MultiLight, PreviewSumsTheLightsOverOneAmbientTerm) {
  const Scene scene = test::squareOverPlane();
  const std::vector<Light> lights = spotAndSun();
  Renderer renderer(ctx(), scene);
  const Image both = renderer.render(test::topDown(), withTechnique(lights, "sm")).image;
  const Image a = renderOne(ctx(), scene, lights[0], "sm").image, b = renderOne(ctx(), scene, lights[1], "sm").image;
  const Camera camera = test::topDown();
  const auto &px = both.require("P.X").data, &py = both.require("P.Y").data, &pz = both.require("P.Z").data;
  const auto &ny = both.require("N.Y").data, &nx = both.require("N.X").data, &nz = both.require("N.Z").data;
  const auto& coverage = both.require("A").data;
  size_t checked = 0;
  for (size_t i = 0; i < coverage.size(); ++i) {
    for (const char* c : {"R", "G", "B"}) {
      if (coverage[i] == 0.0f) {
        EXPECT_EQ(both.require(c).data[i], 0.0f);
        continue;
      }
      glm::vec3 n(nx[i], ny[i], nz[i]);
      if (glm::dot(n, camera.eye - glm::vec3(px[i], py[i], pz[i])) < 0.0f) n = -n;
      const float ambient = kAlbedo * kAmbient * (0.5f + 0.5f * n.y);
      EXPECT_NEAR(both.require(c).data[i] + ambient, a.require(c).data[i] + b.require(c).data[i], kSumTolerance)
          << c << " at " << i;
      ++checked;
    }
  }
  EXPECT_GT(checked, coverage.size());  // most pixels see a surface
}

TEST_F(MultiLight, EachLightMayHaveItsOwnTechnique) {
  const Scene scene = test::squareOverPlane();
  std::vector<Light> lights = spotAndSun();
  lights[0].radius = 0.2f;  // a soft spot for pcss
  std::vector<FrameLight> frame = withTechnique(lights, "sm");
  const TechniqueInfo& pcss = findTechnique("pcss");
  frame[0].technique = &pcss;
  frame[0].params = Params(pcss.params);
  frame[0].params.set("pcss-filter-taps", "4");
  Renderer renderer(ctx(), scene);
  const Image both = renderer.render(test::topDown(), frame).image;
  Renderer single(ctx(), scene);
  const Image key = single.render(test::topDown(), lights[0], pcss, frame[0].params).image;
  const Image sun = renderOne(ctx(), scene, lights[1], "sm").image;
  EXPECT_EQ(both.require("visibility.Key.Y").data, key.require("visibility.Y").data);
  EXPECT_EQ(both.require("visibility.Sun.Y").data, sun.require("visibility.Y").data);
  EXPECT_EQ(both.attributes().at("penumbra:technique"), "pcss");
  const std::string& techniques = both.attributes().at("penumbra:light-techniques");
  EXPECT_NE(techniques.find("Key=pcss ("), std::string::npos) << techniques;
  EXPECT_NE(techniques.find("Sun=sm ("), std::string::npos) << techniques;
}

// Each light's per-frame choices reach the header: the first light's under their own names, the others' under their
// layer's (two moment lights, each picking its blur radius and esm its exponent).
TEST_F(MultiLight, EveryLightRecordsItsAutoChoices) {
  const Scene scene = test::squareOverPlane();
  std::vector<Light> lights = spotAndSun();
  lights[0].radius = 0.2f;
  lights[1].angularRadiusDeg = 2.0f;
  std::vector<FrameLight> frame = withTechnique(lights, "vsm");
  const TechniqueInfo& esm = findTechnique("esm");
  frame[1].technique = &esm;
  frame[1].params = Params(esm.params);
  Renderer renderer(ctx(), scene);
  const Image both = renderer.render(test::topDown(), frame).image;
  const auto& a = both.attributes();
  ASSERT_EQ(a.count("penumbra:blur-radius"), 1u);
  ASSERT_EQ(a.count("penumbra:Sun:blur-radius"), 1u);
  ASSERT_EQ(a.count("penumbra:Sun:esm-exponent"), 1u);
  EXPECT_EQ(a.count("penumbra:esm-exponent"), 0u) << "the first light is vsm's";
  EXPECT_EQ(a.at("penumbra:Sun:blur-radius").rfind("auto ", 0), 0u) << a.at("penumbra:Sun:blur-radius");
  EXPECT_EQ(a.at("penumbra:Sun:esm-exponent").rfind("auto ", 0), 0u) << a.at("penumbra:Sun:esm-exponent");
}

TEST_F(MultiLight, SameNamedLightsGetDistinctLayers) {
  std::vector<Light> lights = spotAndSun();
  lights[0].name = lights[1].name = "Lamp";
  nameLights(lights);
  ASSERT_EQ(lights[1].name, "Lamp-2");
  const Scene scene = test::squareOverPlane();
  Renderer renderer(ctx(), scene);
  const Image both = renderer.render(test::topDown(), withTechnique(lights, "sm")).image;
  EXPECT_NE(both.find("visibility.Lamp.Y"), nullptr);
  EXPECT_NE(both.find("visibility.Lamp-2.Y"), nullptr);
  lights[1].name = "Lamp";  // not made unique: refused rather than one layer overwriting the other
  EXPECT_TRUE(test::throwsWith<std::invalid_argument>(
      [&] { renderer.render(test::topDown(), withTechnique(lights, "sm")); }, {"two lights named \"Lamp\""}));
}

TEST_F(MultiLight, ReferenceTracesEveryLightAndSmMatchesPerLight) {
  const Scene scene = test::squareOverPlane();
  const std::vector<Light> lights = spotAndSun();
  Renderer renderer(ctx(), scene);
  const Image ours = renderer.render(test::topDown(), withTechnique(lights, "sm")).image;
  const reference::ReferenceResult ref = reference::renderReference(ctx(), scene, test::topDown(), lights, {});
  for (const Light& light : lights) {
    ASSERT_NE(ref.image.find(lightChannel("stderr", light.name)), nullptr);
    CompareSpec spec;
    spec.channel = lightChannel("visibility", light.name);
    spec.mask = lightChannel("lit", light.name);
    const ErrorMetrics m = compareImages(ours, ref.image, spec);
    EXPECT_GT(m.pixels, 1000u) << light.name;
    EXPECT_LT(m.mae, 0.01) << light.name;  // hard lights: sm differs only along the shadow's edge pixels
    EXPECT_LT(m.off, 0.02) << light.name;
    // Each light's layer is that light's own single-light reference.
    const reference::ReferenceResult alone = reference::renderReference(ctx(), scene, test::topDown(), light, {});
    EXPECT_EQ(ref.image.require(spec.channel).data, alone.image.require("visibility.Y").data) << light.name;
    EXPECT_EQ(ref.image.require(spec.mask).data, alone.image.require(kLitChannel).data) << light.name;
  }
  EXPECT_EQ(ref.image.require("lit.Y").data, ref.image.require("lit.Key.Y").data);
  EXPECT_NE(ref.image.require("lit.Key.Y").data, ref.image.require("lit.Sun.Y").data);
}

TEST_F(MultiLight, APointLightAmongTheLightsGetsItsOwnLayer) {
  std::vector<Light> lights = spotAndSun();
  Light bulb = parseLight("point:0,4,0");
  bulb.name = "Bulb";
  lights.insert(lights.begin(), bulb);
  const Scene scene = test::squareOverPlane();
  Renderer renderer(ctx(), scene);
  const Image all = renderer.render(test::topDown(), withTechnique(lights, "sm")).image;
  for (const Light& light : lights)  // the point light's faces leave the other lights' frames alone, and vice versa
    EXPECT_EQ(all.require(lightChannel("visibility", light.name)).data,
              renderOne(ctx(), scene, light, "sm").image.require("visibility.Y").data)
        << light.name;
  EXPECT_EQ(all.require("visibility.Y").data, all.require("visibility.Bulb.Y").data);
  EXPECT_TRUE(all.find("cubeFace.Y") != nullptr) << "the first light is a point: its face layer";
  const reference::ReferenceResult ref = reference::renderReference(ctx(), scene, test::topDown(), lights, {});
  CompareSpec spec;
  spec.channel = "visibility.Bulb.Y", spec.mask = "lit.Bulb.Y";
  const ErrorMetrics m = compareImages(all, ref.image, spec);
  EXPECT_GT(m.pixels, 1000u);
  EXPECT_LT(m.off, 0.02);  // a hard point light: sm differs along the shadow's edge pixels only
}

}  // namespace multilight_test
}  // namespace penumbra
