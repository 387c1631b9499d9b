// KHR_lights_punctual import, on glTF files written at run time (the triangle model plus lights): world transforms
// through a rotated and translated parent, cones, ranges and extras sizes, names made unique and channel-safe,
// and malformed light JSON refused with the file and the element named.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "host/scene/gltf_loader.h"
#include "host/scene/light_names.h"
#include "scene_test_util.h"
#include "tests/support/temp_dir.h"

namespace penumbra {
namespace scene_gltf_lights_test {

namespace fs = std::filesystem;
using Json = nlohmann::json;
using test::throwsWith;

constexpr float kTolerance = 1e-5f;  // float round-off of double world transforms
constexpr double kHalf = std::numbers::sqrt2 / 2;
constexpr double kDeg = 180.0 / std::numbers::pi;

// A fresh folder with triangle.bin per test; lights() gives the triangle model with the lights and nodes asked for.
class GltfLights : public ::testing::Test {
 protected:
  void SetUp() override {
    fs::copy_file(test::sceneData("triangle.bin"), dir_ / "triangle.bin");
  }

  // The triangle (node 0) plus `nodes` (appended from index 1, all roots of the scene unless `roots` says which).
  static Json model(const Json& lights, const Json& nodes, Json roots = nullptr) {
    std::ifstream in(test::sceneData("triangle.gltf"));
    Json doc = Json::parse(in);
    doc["extensionsUsed"] = {"KHR_lights_punctual"};
    doc["extensions"]["KHR_lights_punctual"]["lights"] = lights;
    for (const Json& n : nodes) doc["nodes"].push_back(n);
    if (roots.is_null()) {
      roots = Json::array();
      for (size_t i = 0; i < doc["nodes"].size(); ++i) roots.push_back(i);
    }
    doc["scenes"][0]["nodes"] = roots;
    return doc;
  }
  std::string write(const Json& doc, const std::string& name = "lights.gltf") {
    std::ofstream(dir_ / name) << doc.dump();
    return (dir_ / name).string();
  }
  static Json lightNode(int light, Json extra = Json::object()) {
    extra["extensions"]["KHR_lights_punctual"]["light"] = light;
    return extra;
  }
  // One light of `light`'s JSON on one node at the origin.
  std::string single(const Json& light) { return write(model(Json::array({light}), Json::array({lightNode(0)}))); }

  test::TempDir scratch_{"penumbra_lights_test"};  // removed with the fixture
  const fs::path dir_ = scratch_.path();
};

void expectNear(const glm::vec3& actual, const glm::dvec3& expected, const char* what) {
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(actual[k], expected[k], kTolerance) << what << " axis " << k;
}

TEST_F(GltfLights, SpotAndDirectionalUnderARotatedTranslatedParent) {
  const Json lights = {
      {{"type", "spot"},
       {"name", "Key"},
       {"range", 20},
       {"spot", {{"innerConeAngle", 0.2}, {"outerConeAngle", 0.4}}},
       {"extras", {{"penumbra", {{"radius", 0.25}}}}}},
      {{"type", "directional"}, {"name", "Sun"}, {"extras", {{"penumbra", {{"angular_radius_deg", 0.27}}}}}}};
  const double s = std::sin(std::numbers::pi / 8);
  const Json nodes = {
      // node 1: 90 degrees about +Y ((x, y, z) -> (z, y, -x)), then moved to (1, 2, 3)
      {{"name", "rig"}, {"translation", {1, 2, 3}}, {"rotation", {0, kHalf, 0, kHalf}}, {"children", {2, 3}}},
      lightNode(0, {{"translation", {0, 0, 1}}}),                                // node 2
      lightNode(1, {{"rotation", {-s, 0, 0, std::cos(std::numbers::pi / 8)}}}),  // node 3: -45 degrees about X
  };
  const Scene scene = loadGltf(write(model(lights, nodes, {0, 1})));
  ASSERT_EQ(scene.lights.size(), 2u);
  const Light& spot = scene.lights[0];
  EXPECT_EQ(spot.type, LightType::Spot);
  EXPECT_EQ(spot.name, "Key");
  expectNear(spot.position, {2, 2, 3}, "spot position");  // (1, 2, 3) + R (0, 0, 1)
  expectNear(spot.axis(), {-1, 0, 0}, "spot axis");       // R (0, 0, -1)
  EXPECT_NEAR(spot.fovDeg, 2 * 0.4 * kDeg, 1e-4);
  EXPECT_NEAR(spot.innerFovDeg, 2 * 0.2 * kDeg, 1e-4);
  EXPECT_EQ(spot.range, 20.0f);
  EXPECT_EQ(spot.radius, 0.25f);
  const Light& sun = scene.lights[1];
  EXPECT_EQ(sun.type, LightType::Directional);
  EXPECT_EQ(sun.name, "Sun");
  expectNear(sun.direction, {-kHalf, -kHalf, 0}, "sun direction");  // R Rx(-45) (0, 0, -1)
  EXPECT_EQ(sun.angularRadiusDeg, 0.27f);
  EXPECT_EQ(scene.triangleCount(), 1u);
}

TEST_F(GltfLights, GltfDefaultsAndPointLights) {
  const Json lights = {{{"type", "spot"}, {"spot", Json::object()}}, {{"type", "point"}}};
  const Scene scene = loadGltf(write(model(lights, {lightNode(0), lightNode(1, {{"translation", {4, 5, 6}}})})));
  ASSERT_EQ(scene.lights.size(), 2u);
  EXPECT_NEAR(scene.lights[0].fovDeg, 90.0f, 1e-4);  // outerConeAngle defaults to pi/4
  EXPECT_EQ(scene.lights[0].innerFovDeg, 0.0f);
  EXPECT_EQ(scene.lights[0].range, 0.0f);  // unlimited
  EXPECT_EQ(scene.lights[0].radius, 0.0f);
  EXPECT_EQ(scene.lights[1].type, LightType::Point);
  expectNear(scene.lights[1].position, {4, 5, 6}, "point position");
  EXPECT_EQ(scene.lights[1].describe(), "point:4,5,6");
}

TEST_F(GltfLights, OnlyTheDefaultScenesLightsAreImported) {
  Json doc = model(Json::array({{{"type", "point"}}}), {lightNode(0)}, {0});  // node 1 is in no scene
  EXPECT_TRUE(loadGltf(write(doc)).lights.empty());
}

TEST_F(GltfLights, NamesFallBackToTheNodeThenTheIndexAndAreMadeUniqueAndChannelSafe) {
  const Json lights = {{{"type", "point"}, {"name", "Lamp 1.a"}}, {{"type", "point"}}, {{"type", "point"}}};
  const Json nodes = {lightNode(0), lightNode(0), lightNode(1, {{"name", "bulb/left"}}), lightNode(2)};
  const Scene scene = loadGltf(write(model(lights, nodes)));
  std::vector<std::string> names;
  for (const Light& l : scene.lights) names.push_back(l.name);
  EXPECT_EQ(names, (std::vector<std::string>{"Lamp_1_a", "Lamp_1_a-2", "bulb_left", "light2"}));
}

TEST(LightNames, ChannelSafeUniqueAndLookedUp) {
  EXPECT_EQ(channelSafeName("a.b c/d:é"), "a_b_c_d___");  // é is two bytes of UTF-8
  EXPECT_EQ(channelSafeName(std::string(100, 'x')).size(), kMaxLightNameLength);
  std::vector<Light> lights(4);
  lights[0].name = "key", lights[1].name = "key", lights[2].name = "light2", lights[3].name = "";
  nameLights(lights);
  EXPECT_EQ(lights[0].name, "key");
  EXPECT_EQ(lights[1].name, "key-2");
  EXPECT_EQ(lights[2].name, "light2");
  EXPECT_EQ(lights[3].name, "light3");
  EXPECT_EQ(findLight(lights, "2"), 2u);
  EXPECT_EQ(findLight(lights, "key-2"), 1u);
  EXPECT_TRUE(throwsWith<std::invalid_argument>([&] { findLight(lights, "4"); },
                                                {"--light gltf:4", "no light 4", "0 \"key\" (spot)", "3 \"light3\""}));
  EXPECT_TRUE(throwsWith<std::invalid_argument>([&] { findLight(lights, "fill"); }, {"no light named \"fill\""}));
  EXPECT_TRUE(throwsWith<std::invalid_argument>([&] { findLight({}, "0"); }, {"lights: none"}));
}

TEST_F(GltfLights, BadExtrasSizesAreRefused) {
  const auto spotWith = [](const Json& penumbra) {
    return Json{{"type", "spot"}, {"spot", Json::object()}, {"extras", {{"penumbra", penumbra}}}};
  };
  EXPECT_TRUE(throwsWith(
      [&] {
        loadGltf(single(spotWith({{"radius", -1}})));
      },
      {"lights.gltf", "light 0 (node 1)", "extras.penumbra.radius", "[0, 1e+18]"}));
  EXPECT_TRUE(throwsWith([&] { loadGltf(single(spotWith({{"radius", 1e30}}))); },
                         {"extras.penumbra.radius", "[0, 1e+18]"}));
  EXPECT_TRUE(throwsWith([&] { loadGltf(single(spotWith({{"radius", "big"}}))); }, {"extras.penumbra.radius"}));
  EXPECT_TRUE(throwsWith([&] { loadGltf(single(spotWith({{"radus", 1}}))); }, {"extras.penumbra.radus", "unknown"}));
  EXPECT_TRUE(throwsWith([&] { loadGltf(single(spotWith(3))); }, {"extras.penumbra: expected an object"}));
  const Json sun = {{"type", "directional"}, {"extras", {{"penumbra", {{"angular_radius_deg", 50}}}}}};
  EXPECT_TRUE(throwsWith([&] { loadGltf(single(sun)); }, {"extras.penumbra.angular_radius_deg", "[0, 45)"}));
  const Json sunRadius = {{"type", "directional"}, {"extras", {{"penumbra", {{"radius", 1}}}}}};
  EXPECT_TRUE(throwsWith([&] { loadGltf(single(sunRadius)); }, {"directional", "angular_radius_deg"}));
  // Other extras are the file's own business.
  const Json other = {{"type", "point"}, {"extras", {{"blender", {{"size", 3}}}}}};
  EXPECT_EQ(loadGltf(single(other)).lights.at(0).radius, 0.0f);
}

struct BadLight {
  const char* name;
  Json light;  // on node 1 (light index 0 unless `nodeLight` says otherwise)
  Json node;
  std::vector<std::string> parts;
};

class GltfLightsMalformed : public GltfLights, public ::testing::WithParamInterface<BadLight> {};

TEST_P(GltfLightsMalformed, IsRefusedNamingTheFileAndElement) {
  const BadLight& bad = GetParam();
  Json node = bad.node.is_null() ? lightNode(0) : bad.node;
  const std::string path = write(model(Json::array({bad.light}), Json::array({node})));
  std::vector<std::string> parts = bad.parts;
  parts.push_back(path);
  EXPECT_TRUE(throwsWith([&] { loadGltf(path); }, parts));
}

const Json kSpot = {{"type", "spot"}, {"spot", Json::object()}};

INSTANTIATE_TEST_SUITE_P(
    Lights, GltfLightsMalformed,
    ::testing::Values(
        BadLight{"BadType", {{"type", "area"}}, nullptr, {"/extensions/KHR_lights_punctual/lights/0/type", "\"area\""}},
        BadLight{"TypeNotAString", {{"type", 3}}, nullptr, {"/lights/0/type", "a string"}},
        BadLight{"NoType", {{"name", "x"}}, nullptr, {"/lights/0/type", "missing"}},
        BadLight{"SpotWithoutCone", {{"type", "spot"}}, nullptr, {"/lights/0/spot", "missing"}},
        BadLight{"NanCone",
                 {{"type", "spot"}, {"spot", {{"outerConeAngle", "NaN"}}}},
                 nullptr,
                 {"/lights/0/spot/outerConeAngle", "finite number"}},
        BadLight{"InnerNotBelowOuter",
                 {{"type", "spot"}, {"spot", {{"innerConeAngle", 0.5}, {"outerConeAngle", 0.5}}}},
                 nullptr,
                 {"light 0 (node 1)", "innerConeAngle < outerConeAngle"}},
        BadLight{"OuterPastHalfPi",
                 {{"type", "spot"}, {"spot", {{"outerConeAngle", 2.0}}}},
                 nullptr,
                 {"outerConeAngle <= pi/2"}},
        BadLight{"OuterHalfPi",
                 {{"type", "spot"}, {"spot", {{"outerConeAngle", std::numbers::pi / 2}}}},
                 nullptr,
                 {"hemisphere", "not supported yet"}},
        BadLight{"NegativeInner",
                 {{"type", "spot"}, {"spot", {{"innerConeAngle", -0.1}}}},
                 nullptr,
                 {"0 <= innerConeAngle"}},
        BadLight{"ZeroRange", {{"type", "point"}, {"range", 0}}, nullptr, {"/lights/0/range", "positive"}},
        BadLight{"BadColor", {{"type", "point"}, {"color", {1, 1}}}, nullptr, {"/lights/0/color", "3 numbers"}},
        BadLight{"NodeLightOutOfRange",
                 kSpot,
                 Json{{"extensions", {{"KHR_lights_punctual", {{"light", 5}}}}}},
                 {"/nodes/1/extensions/KHR_lights_punctual/light", "no light 5", "has 1"}},
        BadLight{"NodeLightNotAnIndex",
                 kSpot,
                 Json{{"extensions", {{"KHR_lights_punctual", {{"light", -1}}}}}},
                 {"/nodes/1/extensions/KHR_lights_punctual/light", "light index"}},
        BadLight{"NodeLightMissing",
                 kSpot,
                 Json{{"extensions", {{"KHR_lights_punctual", Json::object()}}}},
                 {"/nodes/1/extensions/KHR_lights_punctual/light", "missing"}},
        // A zero scale leaves the light's -Z axis zero: its direction would be NaN.
        BadLight{"ZeroScaleDirection",
                 kSpot,
                 Json{{"scale", {0, 0, 0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}},
                 {"light 0 (node 1)", "no direction"}}),
    [](const auto& test) { return std::string(test.param.name); });

}  // namespace scene_gltf_lights_test
}  // namespace penumbra
