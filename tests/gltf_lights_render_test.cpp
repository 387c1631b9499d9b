// Lights from glTF files through the renderer: a spot light read from KHR_lights_punctual renders bit for bit
// like the same spot given on the command line; a generated file with a camera and a point light (a sphere light
// by its extras) renders with the file's camera and light alone and matches the reference; the preview falls off
// between a glTF spot's inner and outer cone as KHR_lights_punctual prescribes.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <stdexcept>

#include "host/eval/metrics.h"
#include "host/pipeline/renderer.h"
#include "host/scene/gltf_loader.h"
#include "host/scene/light_names.h"
#include "host/techniques/registry.h"
#include "host/techniques/technique.h"
#include "scene_test_util.h"
#include "tests/support/cl_test.h"
#include "tests/support/gltf_builder.h"
#include "tests/support/render.h"
#include "tests/support/temp_dir.h"
#include "tools/reference/reference.h"
#include "tools/selftest/reference/analytic_scenes.h"

namespace penumbra {
namespace gltf_lights_render_test {

namespace fs = std::filesystem;
using Json = nlohmann::json;

// The triangle model plus one light on a node placed by `matrix`, loaded back; only the light is used.
Light lightFromGltf(const Json& light, const std::vector<double>& matrix) {
  const fs::path dir = fs::temp_directory_path() / ("penumbra_lights_render_" + std::to_string(getpid()));
  fs::create_directories(dir);
  fs::copy_file(test::sceneData("triangle.bin"), dir / "triangle.bin", fs::copy_options::overwrite_existing);
  std::ifstream in(test::sceneData("triangle.gltf"));
  Json doc = Json::parse(in);
  doc["extensions"]["KHR_lights_punctual"]["lights"] = {light};
  doc["nodes"].push_back({{"matrix", matrix}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  doc["scenes"][0]["nodes"] = {0, 1};
  std::ofstream(dir / "light.gltf") << doc.dump();
  const Scene scene = loadGltf((dir / "light.gltf").string());
  fs::remove_all(dir);
  EXPECT_EQ(scene.lights.size(), 1u);
  return scene.lights.at(0);
}

class GltfLightsRender : public test::ClTest {};

// A sphere light through pcss and vssm against the 64-spp area reference: the soft techniques' usual bounds
// (tests/camera_render_test.cpp's for pcss under a disk light).
constexpr double kSoftMaxMae = 0.01;
constexpr double kSoftMaxOff = 0.02;

TEST_F(GltfLightsRender, FileSpotRendersLikeTheCommandLineSpot) {
  // Local -Z onto world -Y exactly (columns (1,0,0), (0,0,-1), (0,1,0)), at (0, 4, 0); a 120 degree cone.
  const std::vector<double> down = {1, 0, 0, 0, 0, 0, -1, 0, 0, 1, 0, 0, 0, 4, 0, 1};
  const Json spot = {{"type", "spot"},
                     {"name", "Key"},
                     {"spot", {{"outerConeAngle", std::numbers::pi / 3}}},
                     {"extras", {{"penumbra", {{"radius", 0.1}}}}}};
  const Light fromFile = lightFromGltf(spot, down);
  const Light fromCli = parseLight("spot:0,4,0:0,3,0:120:0.1");
  for (const char* technique : {"sm", "pcss"}) {
    const Image a = test::renderWith(ctx(), test::squareOverPlane(), test::topDown(), fromFile, technique).image;
    const Image b = test::renderWith(ctx(), test::squareOverPlane(), test::topDown(), fromCli, technique).image;
    EXPECT_EQ(a.require("visibility.Y").data, b.require("visibility.Y").data) << technique;
    EXPECT_EQ(a.attributes().at("penumbra:light-name"), "Key");
    EXPECT_EQ(a.attributes().at("penumbra:light"), fromCli.describe());
  }
}

TEST_F(GltfLightsRender, PreviewFallsOffBetweenTheInnerAndOuterCone) {
  // KHR_lights_punctual's angular attenuation, ((cos - cos outer) / (cos inner - cos outer))^2 clamped, in the preview
  // of every lit pixel: R = 0.75 (n.l attenuation + 0.12 sky) (kernels/shade.cl). The file's spot above (a 60 degree
  // inner cone in a 120 degree one) from the light's own inner angle; a spot without one keeps the old preview.
  const std::vector<double> down = {1, 0, 0, 0, 0, 0, -1, 0, 0, 1, 0, 0, 0, 4, 0, 1};
  const Json spot = {{"type", "spot"},
                     {"spot", {{"innerConeAngle", std::numbers::pi / 6}, {"outerConeAngle", std::numbers::pi / 3}}}};
  const Light light = lightFromGltf(spot, down);
  ASSERT_NEAR(light.innerFovDeg, 60.0f, 1e-3f);
  const Image image = test::renderWith(ctx(), test::squareOverPlane(), test::topDown(), light, "sm").image;
  const auto &r = image.require("R").data, &vis = image.require("visibility.Y").data, &a = image.require("A").data;
  const auto &px = image.require("P.X").data, &py = image.require("P.Y").data, &pz = image.require("P.Z").data;
  const auto& ny = image.require("N.Y").data;
  const float cosOuter = std::cos(glm::radians(60.0f)), cosInner = std::cos(glm::radians(30.0f));
  size_t band = 0, checked = 0;
  for (size_t i = 0; i < r.size(); ++i) {
    if (a[i] == 0.0f || vis[i] != 1.0f || ny[i] < 0.999f) continue;  // lit ground (normal +Y)
    const glm::vec3 toLight = glm::normalize(light.position - glm::vec3(px[i], py[i], pz[i]));
    const float t = std::clamp((toLight.y - cosOuter) / (cosInner - cosOuter), 0.0f, 1.0f);  // axis -Y
    const float expected = 0.75f * (std::max(toLight.y, 0.0f) * t * t + 0.12f * (0.5f + 0.5f * ny[i]));
    ASSERT_NEAR(r[i], expected, 2e-4f) << i;
    band += t > 0.05f && t < 0.95f;
    ++checked;
  }
  EXPECT_GT(checked, 1000u);
  EXPECT_GT(band, 200u) << "pixels inside the falloff band";
  Light plain = light;
  plain.innerFovDeg = -1.0f;  // no inner cone: the preview's own falloff, brighter between the cones
  const Image old = test::renderWith(ctx(), test::squareOverPlane(), test::topDown(), plain, "sm").image;
  EXPECT_EQ(old.require("visibility.Y").data, vis);
  EXPECT_NE(old.require("R").data, r);
}

// KHR_lights_punctual's range: the preview fades a point light out as clamp(1 - (d / range)^4, 0, 1) (the extension's
// recommended window; the preview has no 1 / d^2 for any light) and leaves visibility alone.
TEST_F(GltfLightsRender, PreviewFadesAPointLightOutAtItsRange) {
  const std::vector<double> above = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 4, 0, 1};
  const Light light = lightFromGltf({{"type", "point"}, {"range", 5.0}}, above);
  ASSERT_FLOAT_EQ(light.range, 5.0f);
  const Image image = test::renderWith(ctx(), test::squareOverPlane(), test::topDown(), light, "sm").image;
  const auto &r = image.require("R").data, &vis = image.require("visibility.Y").data, &a = image.require("A").data;
  const auto &px = image.require("P.X").data, &py = image.require("P.Y").data, &pz = image.require("P.Z").data;
  const auto& ny = image.require("N.Y").data;
  size_t faded = 0, dark = 0, checked = 0;
  for (size_t i = 0; i < r.size(); ++i) {
    if (a[i] == 0.0f || vis[i] != 1.0f || ny[i] < 0.999f) continue;  // lit ground (normal +Y)
    const glm::vec3 d = light.position - glm::vec3(px[i], py[i], pz[i]);
    const float q = glm::length(d) / 5.0f, window = std::clamp(1.0f - q * q * q * q, 0.0f, 1.0f);
    const float expected = 0.75f * (std::max(glm::normalize(d).y, 0.0f) * window + 0.12f * (0.5f + 0.5f * ny[i]));
    ASSERT_NEAR(r[i], expected, 2e-4f) << i;
    faded += window > 0.05f && window < 0.95f, dark += window == 0.0f, ++checked;
  }
  EXPECT_GT(faded, 500u) << "pixels inside the fade";
  EXPECT_GT(dark, 100u) << "ground beyond the range";
  Light unlimited = light;
  unlimited.range = 0.0f;
  const Image full = test::renderWith(ctx(), test::squareOverPlane(), test::topDown(), unlimited, "sm").image;
  EXPECT_EQ(full.require("visibility.Y").data, vis);
}

// A 8x8 ground, a slab floating above it and a perspective camera looking down at both; the caller adds lights.
test::GltfBuilder slabWithCamera() {
  std::vector<glm::vec3> soup;
  test::addQuadY(soup, 0.0f, 4.0f);
  test::addBox(soup, {0.8f, 0.9f, -0.6f}, {1.8f, 1.0f, 0.6f});
  test::GltfBuilder b(soup);
  const int camera = b.addCamera(
      {{"type", "perspective"}, {"perspective", {{"yfov", 1.0}, {"aspectRatio", 4.0 / 3}, {"znear", 0.1}}}});
  const double s = std::sin(glm::radians(-25.0)), c = std::cos(glm::radians(-25.0));
  b.addNode({{"camera", camera}, {"translation", {0.5, 4.5, 7.0}}, {"rotation", {s, 0, 0, c}}});
  b.doc()["extensionsUsed"] = {"KHR_lights_punctual"};
  return b;
}

// slabWithCamera with a point light of radius 0.1 (extras) above the slab's inner edge, so that the slab's shadow crosses the edge between the light's -Y and +X cube faces.
Scene pointLightScene(const fs::path& dir) {
  test::GltfBuilder b = slabWithCamera();
  b.doc()["extensions"]["KHR_lights_punctual"]["lights"] = {
      {{"type", "point"}, {"name", "Bulb"}, {"extras", {{"penumbra", {{"radius", 0.1}}}}}}};
  b.addNode({{"translation", {0.3, 2.2, 0.1}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  return loadGltf(b.write(dir, "bulb"));
}

TEST_F(GltfLightsRender, FilePointLightWithTheFilesCameraMatchesTheReference) {
  const test::TempDir dir("penumbra_gltf_point_light");
  const Scene scene = pointLightScene(dir.path());
  ASSERT_EQ(scene.lights.size(), 1u);
  ASSERT_EQ(scene.cameras.size(), 1u);
  const Light& bulb = scene.lights[0];
  ASSERT_EQ(bulb.type, LightType::Point);
  EXPECT_EQ(bulb.name, "Bulb");
  EXPECT_EQ(bulb.radius, 0.1f);
  Camera camera = scene.cameras[0];  // the file's camera and light, nothing given on top but a small image
  camera.width = 160, camera.height = 120;
  reference::TraceSettings settings;
  settings.spp = 64;
  const reference::ReferenceResult ref = reference::renderReference(ctx(), scene, camera, bulb, settings);
  for (const char* technique : {"pcss", "vssm"}) {  // the two soft techniques for a sphere light (pcss: the default)
    const RenderResult ours = test::renderWith(ctx(), scene, camera, bulb, technique, {{"map-size", "512"}});
    ASSERT_TRUE(test::saneImage(ours.image, technique));
    const ErrorMetrics m = compareImages(ours.image, ref.image);
    std::printf("%s: %zu pixels, mae %.4f, off %.4f, %s\n", technique, m.pixels, m.mae, m.off,
                ours.image.attributes().at("penumbra:cube").c_str());
    EXPECT_GT(m.pixels, 5000u) << technique;
    EXPECT_LT(m.mae, kSoftMaxMae) << technique;
    EXPECT_LT(m.off, kSoftMaxOff) << technique;
    EXPECT_EQ(ours.image.attributes().at("penumbra:light-name"), "Bulb");
    EXPECT_NE(ours.image.attributes().at("penumbra:cube").find("-Y"), std::string::npos);
    EXPECT_NE(ours.image.attributes().at("penumbra:cube").find("+X"), std::string::npos);
  }
}

// The issue's file: a camera and a spot, a directional and a point light (all hard), rendered with nothing given but
// the image size: every light of the file in one frame, each in its own layer, each matching its layer of the
// reference traced for the same lights.
TEST_F(GltfLightsRender, FileWithCameraSpotSunAndPointMatchesTheReferencePerLight) {
  const test::TempDir dir("penumbra_gltf_three_lights");
  test::GltfBuilder b = slabWithCamera();
  b.doc()["extensions"]["KHR_lights_punctual"]["lights"] = {
      {{"type", "spot"}, {"name", "Key"}, {"spot", {{"outerConeAngle", 1.0}}}},
      {{"type", "directional"}, {"name", "Sun"}},
      {{"type", "point"}, {"name", "Bulb"}}};
  const double q = std::sqrt(0.5);  // -90 degrees about +X: local -Z (the spot's axis) to world -Y
  b.addNode({{"translation", {-1.0, 5.0, 0.5}},
             {"rotation", {-q, 0, 0, q}},
             {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  b.addNode({{"rotation", {-0.35, 0.1, 0, 0.93}}, {"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});
  b.addNode({{"translation", {0.3, 2.2, 0.1}}, {"extensions", {{"KHR_lights_punctual", {{"light", 2}}}}}});
  const Scene scene = loadGltf(b.write(dir.path(), "three"));
  ASSERT_EQ(scene.lights.size(), 3u);
  ASSERT_EQ(scene.cameras.size(), 1u);
  Camera view = scene.cameras[0];
  view.width = 160, view.height = 120;
  const TechniqueInfo& sm = findTechnique("sm");
  std::vector<FrameLight> frame;
  for (const Light& light : scene.lights) {
    Params params(sm.params);
    params.set("map-size", "512");
    frame.push_back({light, &sm, params});
  }
  Renderer renderer(ctx(), scene);
  const Image ours = renderer.render(view, frame).image;
  const reference::ReferenceResult ref = reference::renderReference(ctx(), scene, view, scene.lights, {});
  for (const Light& light : scene.lights) {
    CompareSpec spec;
    spec.channel = lightChannel("visibility", light.name);
    spec.mask = lightChannel("lit", light.name);
    const ErrorMetrics m = compareImages(ours, ref.image, spec);
    EXPECT_GT(m.pixels, 3000u) << light.name;
    EXPECT_LT(m.mae, 0.01) << light.name;  // hard lights: sm differs only along the shadows' edge pixels
    EXPECT_LT(m.off, 0.02) << light.name;
    const auto& v = ours.require(spec.channel).data;
    EXPECT_LT(*std::min_element(v.begin(), v.end()), 0.5f) << light.name << ": the slab shadows the ground";
  }
}

}  // namespace gltf_lights_render_test
}  // namespace penumbra
