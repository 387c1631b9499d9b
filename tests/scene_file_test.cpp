// JSON scene files: composition (placed models, built-in scenes, ground, views), ground placement, every
// bundled scene file (the camera sees the model, the light's cone holds it), and the errors for unknown
// keys and bad values, each naming the file and the JSON pointer.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "host/scene/scene_file.h"
#include "scene_test_util.h"
#include "tests/support/temp_dir.h"

namespace penumbra {
namespace scene_file_test {

namespace fs = std::filesystem;
using test::throwsWith;

constexpr float kPlacementTolerance = 1e-5f;  // float round-off of composed placements on unit inputs

// A temporary folder holding triangle.gltf/.bin; JSON scene files are written next to them.
class SceneFile : public ::testing::Test {
 protected:
  void SetUp() override {
    for (const char* f : {"triangle.gltf", "triangle.bin"}) fs::copy_file(test::sceneData(f), dir_ / f);
  }
  std::string write(const std::string& json, const std::string& name = "scene.json") {
    std::ofstream(dir_ / name) << json;
    return (dir_ / name).string();
  }
  Scene load(const std::string& json) { return loadSceneFile(write(json)); }
  ::testing::AssertionResult refused(const std::string& json, const std::vector<std::string>& parts) {
    std::vector<std::string> all = parts;
    all.push_back("scene.json: ");
    return throwsWith([&] { loadSceneFile(write(json)); }, all);
  }
  test::TempDir scratch_{"penumbra_scene_file_test"};  // removed with the fixture
  const fs::path dir_ = scratch_.path();
};

TEST_F(SceneFile, ComposesModelsBuiltinsGroundAndViews) {
  const Scene s = load(R"({
    "models": [{"path": "triangle.gltf", "translation": [10, 0, 0]},
               {"path": "triangle.gltf", "rotation_deg": [0, 90, 0], "scale": 2},
               {"path": "triangle.gltf", "rotation_quat": [0, 0, 0, 1], "scale": [-1, 1, 1]}],
    "procedural": [{"name": "box", "size": 0.5}],
    "camera": {"eye": [0, 5, 10], "target": [0, 0, 0], "fovy_deg": 50, "size": [640, 480]},
    "cameras": [{"eye": [1, 1, 1], "target": [0, 0, 0]}],
    "lights": [{"type": "spot", "position": [0, 10, 0], "target": [0, 0, 0], "fov_deg": 40, "radius": 0.5},
               {"type": "dir", "direction": [0, -2, 0], "angular_radius_deg": 0.25}]
  })");
  EXPECT_EQ(s.triangleCount(), 3u + 2u + 12u);  // three placed triangles, box ground and box
  EXPECT_TRUE(test::wellFormed(s));
  EXPECT_TRUE(test::windingMatchesNormals(s, 0.999f));
  EXPECT_EQ(s.positions[s.triangles[0].y], glm::vec3(11, 0, 0));
  EXPECT_NEAR(glm::distance(s.positions[s.triangles[1].y], glm::vec3(0, 0, -2)), 0.0f, kPlacementTolerance);
  EXPECT_EQ(s.positions[s.triangles[2].z], glm::vec3(-1, 0, 0));  // mirrored: winding reversed
  ASSERT_EQ(s.cameras.size(), 2u);                                // replace the box's own camera
  EXPECT_EQ(s.cameras[0].width, 640);
  EXPECT_EQ(s.cameras[0].fovYDeg, 50.0f);
  EXPECT_EQ(s.cameras[1].width, 1280);
  ASSERT_EQ(s.lights.size(), 2u);
  EXPECT_EQ(s.lights[1].direction, glm::vec3(0, -1, 0));
}

TEST_F(SceneFile, BuiltinViewsStayWhenTheFileGivesNone) {
  const Scene s = load(R"({"procedural": [{"name": "staircase"}]})");
  EXPECT_EQ(s.cameras.size(), 1u);
  EXPECT_EQ(s.lights.size(), 1u);
}

TEST_F(SceneFile, GroundUnderTheModels) {
  const Scene s = load(R"({"models": [{"path": "triangle.gltf", "translation": [0, 2, 0]}], "ground": {}})");
  ASSERT_EQ(s.objectNames.back(), "ground");
  ASSERT_EQ(s.triangleCount(), 3u);
  Bounds ground;
  for (size_t t = 1; t < 3; ++t)
    for (int k = 0; k < 3; ++k) ground.grow(s.positions[s.triangles[t][k]]);
  EXPECT_EQ(ground.min, glm::vec3(-1, 2, -1));  // margin 1 x max(width 1, depth 0) on each side
  EXPECT_EQ(ground.max, glm::vec3(2, 2, 1));
  for (size_t v = 3; v < s.positions.size(); ++v) EXPECT_EQ(s.normals[v], glm::vec3(0, 1, 0));
  EXPECT_TRUE(test::windingMatchesNormals(s, 0.999f));
  const Scene low = load(R"({"models": [{"path": "triangle.gltf"}], "ground": {"y": -1.5, "margin": 0.5}})");
  EXPECT_EQ(low.bounds().min, glm::vec3(-0.5f, -1.5f, -0.5f));
  EXPECT_EQ(load(R"({"models": [{"path": "triangle.gltf"}], "ground": {"enabled": false}})").triangleCount(), 1u);
}

struct BadFile {
  const char* json;
  std::vector<std::string> parts;
};

class SceneFileBad : public SceneFile, public ::testing::WithParamInterface<BadFile> {};

TEST_P(SceneFileBad, RefusedNamingThePointer) { EXPECT_TRUE(refused(GetParam().json, GetParam().parts)); }

INSTANTIATE_TEST_SUITE_P(
    SceneFile, SceneFileBad,
    ::testing::Values(
        BadFile{"{}", {"no triangles"}}, BadFile{"[]", {"(root): expected an object"}},
        BadFile{"{\"models\": [", {"invalid JSON"}}, BadFile{R"({"modles": []})", {"/modles: unknown key"}},
        BadFile{R"({"models": [{"path": "triangle.gltf", "translaton": [1, 2, 3]}]})",
                {"/models/0/translaton: unknown key"}},
        BadFile{R"({"models": {"path": "triangle.gltf"}})", {"/models: expected an array"}},
        BadFile{R"({"models": [{"path": "triangle.gltf"}], "models": []})", {"duplicate key \"models\""}},
        BadFile{R"({"models": [{}]})", {"/models/0/path: missing"}},
        BadFile{R"({"models": [{"path": "../nothere.gltf"}]})", {"/models/0/path", "file not found (looked for /"}},
        BadFile{R"({"models": [{"path": "/nonexistent/triangle.gltf"}]})",
                {"/models/0/path", "file not found (looked for /nonexistent/triangle.gltf)"}},
        BadFile{R"({"models": [{"path": "file:///tmp/triangle.gltf"}]})", {"/models/0/path", "URI schemes"}},
        BadFile{R"({"models": [{"path": "tri\u0000angle.gltf"}]})",
                {"/models/0/path: \"tri\\0angle.gltf\": path contains a NUL byte"}},
        BadFile{R"({"models": [{"path": "nothere.glb"}]})", {"/models/0/path", "file not found"}},
        BadFile{R"({"models": [{"path": "triangle.obj"}]})", {"/models/0/path", "not a .gltf or .glb"}},
        BadFile{R"({"models": [{"path": "triangle.gltf", "translation": [1, 2]}]})",
                {"/models/0/translation", "3 finite numbers"}},
        BadFile{R"({"models": [{"path": "triangle.gltf", "scale": 0}]})", {"/models/0/scale", "non-zero"}},
        BadFile{R"({"models": [{"path": "triangle.gltf", "rotation_deg": [0, 0, 0], "rotation_quat": [0, 0, 0, 1]}]})",
                {"/models/0/rotation_quat", "not both"}},
        BadFile{R"({"models": [{"path": "triangle.gltf", "rotation_quat": [0, 0, 0, 0]}]})", {"zero quaternion"}},
        BadFile{R"({"procedural": [{"name": "box", "size": 1e30}]})", {"/procedural/0", "size = 1e+30 is outside"}},
        BadFile{R"({"procedural": [{"name": "boxx"}]})", {"/procedural/0", "unknown built-in scene"}},
        // Checked before any geometry is built: eight million-pole scenes (96 M triangles), a misspelled key beside
        // a large one (it used to come out after 12 M triangles were built).
        BadFile{
            R"({"procedural": [)"
            R"({"name": "poles", "rows": 1000, "columns": 1000}, {"name": "poles", "rows": 1000, "columns": 1000}, {"name": "poles", "rows": 1000, "columns": 1000}, {"name": "poles", "rows": 1000, "columns": 1000}, {"name": "poles", "rows": 1000, "columns": 1000}, {"name": "poles", "rows": 1000, "columns": 1000}, {"name": "poles", "rows": 1000, "columns": 1000}, {"name": "poles", "rows": 1000, "columns": 1000}]})",
            {"/procedural: the built-in scenes make 96000016 triangles, more than the limit of 67108864"}},
        BadFile{R"({"procedural": [{"name": "poles", "rows": 1000, "columns": 1000}], "lihgts": []})",
                {"/lihgts: unknown key"}},
        BadFile{R"({"procedural": [{"name": "box", "size": "big"}]})", {"/procedural/0/size: expected a number"}},
        BadFile{R"({"procedural": [{"name": "box", "colour": 1}]})", {"/procedural/0", "unknown parameter \"colour\""}},
        BadFile{R"({"ground": {}})", {"/ground", "no models"}},
        BadFile{R"({"procedural": [{"name": "box"}], "ground": {"margin": -1}})",
                {"/ground/margin: expected a number in [0, 1000]"}},
        BadFile{R"({"procedural": [{"name": "box"}], "ground": {"enabled": 1}})",
                {"/ground/enabled: expected true or false"}},
        BadFile{R"({"procedural": [{"name": "box"}], "ground": {"heigth": 1}})", {"/ground/heigth: unknown key"}},
        BadFile{R"({"procedural": [{"name": "box"}], "camera": {"eye": [0, 1, 0], "target": [0, 1, 0]}})",
                {"/camera/target: equals eye"}},
        BadFile{
            R"({"procedural": [{"name": "box"}], "camera": {"eye": [0, 1, 5], "target": [0, 0, 0], "fovy_deg": 180}})",
            {"/camera/fovy_deg: expected a number in (0, 180)"}},
        BadFile{
            R"({"procedural": [{"name": "box"}], "camera": {"eye": [0, 1, 5], "target": [0, 0, 0], "size": [0, 720]}})",
            {"/camera/size: expected [width, height]"}},
        BadFile{R"({"procedural": [{"name": "box"}], "cameras": [{"eye": [0, 1, 5]}]})",
                {"/cameras/0/target: missing"}},
        BadFile{R"({"procedural": [{"name": "box"}], "lights": []})", {"/lights: is empty"}},
        BadFile{R"({"procedural": [{"name": "box"}], "lights": [{"type": "spot", "position": [0, 5, 0], )"
                R"("target": [0, 0, 0], "fov_deg": 200}]})",
                {"/lights/0/fov_deg: expected a number in (0, 180)"}},
        BadFile{R"({"procedural": [{"name": "box"}], "lights": [{"type": "spot", "position": [0, 5, 0], )"
                R"("target": [0, 0, 0], "radius": -1}]})",
                {"/lights/0/radius: expected a number in [0, 1e+18]"}},
        // 1e300 used to be accepted (as inf) and the Embree reference aborted on it.
        BadFile{R"({"procedural": [{"name": "box"}], "lights": [{"type": "point", "position": [0, 5, 0], )"
                R"("radius": 1e300}]})",
                {"/lights/0/radius: expected a number in [0, 1e+18]"}},
        BadFile{R"({"procedural": [{"name": "box"}], "lights": [{"type": "dir", "direction": [0, 0, 0]}]})",
                {"/lights/0/direction: must not be the zero vector"}},
        BadFile{
            R"({"procedural": [{"name": "box"}], "lights": [{"type": "dir", "direction": [0, -1, 0], "radius": 1}]})",
            {"/lights/0/radius: unknown key"}},
        BadFile{R"({"procedural": [{"name": "box"}], "lights": [{"type": "dir", "direction": [0, -1, 0], )"
                R"("angular_radius_deg": 45}]})",
                {"/lights/0/angular_radius_deg: expected a number in [0, 45)"}},
        BadFile{R"({"procedural": [{"name": "box"}], "lights": [{"type": "area"}]})",
                {"/lights/0/type: expected \"spot\", \"dir\" or \"point\""}},
        BadFile{R"({"procedural": [{"name": "box"}], "lights": [{"type": "point"}]})", {"/lights/0/position"}}));

// triangle.gltf plus a spot light "Lamp" at (0, 5, 0) shining down and a directional "Sun" (KHR_lights_punctual).
void writeLitModel(const fs::path& dir) {
  std::ifstream in(dir / "triangle.gltf");
  nlohmann::json doc = nlohmann::json::parse(in);
  doc["extensions"]["KHR_lights_punctual"]["lights"] = {
      {{"type", "spot"}, {"name", "Lamp"}, {"spot", nlohmann::json::object()}},
      {{"type", "directional"}, {"name", "Sun"}}};
  const std::vector<double> down = {1, 0, 0, 0, 0, 0, -1, 0, 0, 1, 0, 0, 0, 5, 0, 1};  // local -Z onto world -Y
  doc["nodes"].push_back({{"matrix", down}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  doc["nodes"].push_back({{"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});
  doc["scenes"][0]["nodes"] = {0, 1, 2};
  std::ofstream(dir / "lit.gltf") << doc.dump();
}

TEST_F(SceneFile, ModelLightsMoveWithTheirPlacementAndTakeSizesByName) {
  writeLitModel(dir_);
  const Scene s = load(R"({"models": [{"path": "lit.gltf", "translation": [10, 0, 0], "scale": 2},
                                      {"path": "lit.gltf"}],
                           "lights": [{"name": "Lamp", "radius": 0.3}, {"name": "Lamp-2", "radius": 0.1},
                                      {"name": "Sun", "angular_radius_deg": 0.5}]})");
  ASSERT_EQ(s.lights.size(), 4u);
  EXPECT_EQ(s.lights[0].name, "Lamp");
  EXPECT_EQ(s.lights[0].position, glm::vec3(10, 10, 0));  // scaled by 2, then moved
  EXPECT_EQ(s.lights[0].axis(), glm::vec3(0, -1, 0));
  EXPECT_EQ(s.lights[0].radius, 0.3f);  // the placement's scale changes no size
  EXPECT_EQ(s.lights[1].name, "Sun");
  EXPECT_EQ(s.lights[1].angularRadiusDeg, 0.5f);
  EXPECT_EQ(s.lights[2].name, "Lamp-2");
  EXPECT_EQ(s.lights[2].position, glm::vec3(0, 5, 0));
  EXPECT_EQ(s.lights[2].radius, 0.1f);
  EXPECT_EQ(s.lights[3].name, "Sun-2");
  EXPECT_EQ(s.lights[3].angularRadiusDeg, 0.0f);
}

TEST_F(SceneFile, LightsMayNameTheirOwnTechnique) {
  const Scene s = load(R"({"procedural": [{"name": "box"}], "lights": [
    {"name": "Key", "type": "spot", "position": [0, 5, 0], "target": [0, 0, 0], "technique": "pcss",
     "params": {"pcss-filter-taps": 4, "fit": "receivers", "receiver-plane": true}},
    {"name": "Sun", "type": "dir", "direction": [0, -1, 0]}]})");
  ASSERT_EQ(s.lights.size(), 2u);
  EXPECT_EQ(s.lights[0].technique, "pcss");
  EXPECT_EQ(s.lights[0].params, (std::map<std::string, std::string>{
                                    {"fit", "receivers"}, {"pcss-filter-taps", "4"}, {"receiver-plane", "on"}}));
  EXPECT_TRUE(s.lights[1].technique.empty());
  EXPECT_TRUE(s.lights[1].params.empty());
  const std::string spot = R"("type": "spot", "position": [0, 5, 0], "target": [0, 0, 0])";
  EXPECT_TRUE(refused(R"({"procedural": [{"name": "box"}], "lights": [{)" + spot + R"(, "params": {"bias": 1}}]})",
                      {"/lights/0/params: needs \"technique\" beside it"}));
  EXPECT_TRUE(refused(R"({"procedural": [{"name": "box"}], "lights": [{)" + spot + R"(, "technique": ""}]})",
                      {"/lights/0/technique: is empty"}));
  EXPECT_TRUE(
      refused(R"({"procedural": [{"name": "box"}], "lights": [{)" + spot + R"(, "technique": "sm", "params": [1]}]})",
              {"/lights/0/params: expected an object"}));
  EXPECT_TRUE(refused(
      R"({"procedural": [{"name": "box"}], "lights": [{)" + spot + R"(, "technique": "sm", "params": {"bias": [1]}}]})",
      {"/lights/0/params/bias: expected a number, a string or a boolean"}));
}

TEST_F(SceneFile, LightSizesNameALightOfTheModels) {
  writeLitModel(dir_);
  EXPECT_TRUE(refused(R"({"models": [{"path": "lit.gltf"}], "lights": [{"name": "Fill", "radius": 1}]})",
                      {"/lights/0/name", "no light named \"Fill\"", "0 \"Lamp\" (spot), 1 \"Sun\" (dir)"}));
  EXPECT_TRUE(refused(R"({"models": [{"path": "lit.gltf"}], "lights": [{"name": "Sun", "radius": 1}]})",
                      {"/lights/0/radius", "directional"}));
  EXPECT_TRUE(refused(R"({"models": [{"path": "lit.gltf"}], "lights": [{"name": "Lamp", "radius": -1}]})",
                      {"/lights/0/radius", "[0, 1e+18]"}));
  EXPECT_TRUE(refused(R"({"models": [{"path": "lit.gltf"}], "lights": [{"name": "Lamp"}]})", {"/lights/0/radius"}));
  EXPECT_TRUE(refused(R"({"models": [{"path": "lit.gltf"}],
                          "lights": [{"name": "Lamp", "radius": 1}, {"type": "dir", "direction": [0, -1, 0]}]})",
                      {"/lights/0", "also defines lights"}));
}

TEST_F(SceneFile, DefinedLightsMayBePointsAndGetUniqueNames) {
  writeLitModel(dir_);
  const Scene s = load(R"({"models": [{"path": "lit.gltf"}],
                           "lights": [{"type": "point", "position": [0, 3, 0], "radius": 0.2, "name": "bulb 1"},
                                      {"type": "dir", "direction": [0, -1, 0]}]})");
  ASSERT_EQ(s.lights.size(), 2u);  // the defined lights replace the model's
  EXPECT_EQ(s.lights[0].type, LightType::Point);
  EXPECT_EQ(s.lights[0].name, "bulb_1");
  EXPECT_EQ(s.lights[0].radius, 0.2f);
  EXPECT_EQ(s.lights[1].name, "light1");
}

// A scene file is the user's own: its models may sit anywhere (absolute paths, ".." from the scene's folder).
TEST_F(SceneFile, ModelsByAbsolutePathAndDotDot) {
  fs::create_directories(dir_ / "scenes");
  const std::string json =
      R"({"models": [{"path": "../triangle.gltf"}, {"path": ")" + (dir_ / "triangle.gltf").string() + R"("}]})";
  const Scene s = loadSceneFile(write(json, "scenes/scene.json"));
  EXPECT_EQ(s.triangleCount(), 2u);
  EXPECT_TRUE(test::wellFormed(s));
}

// ... but the URIs inside a model stay in the model's own folder, wherever the model is.
TEST_F(SceneFile, ModelUrisStayInsideTheModelsFolder) {
  fs::create_directories(dir_ / "models");
  fs::copy_file(test::sceneData("malformed/traversal.gltf"), dir_ / "models/traversal.gltf");
  EXPECT_TRUE(throwsWith([&] { loadSceneFile(write(R"({"models": [{"path": "models/traversal.gltf"}]})")); },
                         {"scene.json: /models/0", "its \"..\" components leave the scene's folder"}));
}

TEST_F(SceneFile, ModelErrorsNameTheEntryAndTheModel) {
  std::ofstream(dir_ / "broken.gltf") << "{\"asset\": {\"version\": \"2.0\"}, \"scene\": 5}";
  EXPECT_TRUE(throwsWith([&] { loadSceneFile(write(R"({"models": [{"path": "broken.gltf"}]})")); },
                         {"scene.json: /models/0: broken.gltf: /scene: no element 5 in scenes"}));
}

// Every bundled scene file: the model and a ground, a 1280x720 camera that sees the whole model, and a
// soft spot light whose cone holds the model.
class SceneFileBundled : public ::testing::TestWithParam<std::string> {};

TEST_P(SceneFileBundled, CameraAndLightFrameTheModel) {
  const Scene s = loadSceneFile(test::bundledScene(GetParam()));
  EXPECT_TRUE(test::wellFormed(s));
  ASSERT_EQ(s.objectNames.back(), "ground");
  Bounds model;
  for (size_t t = 0; t < s.triangleCount(); ++t)
    if (s.objectNames[s.objectIds[t]] != "ground")
      for (int k = 0; k < 3; ++k) model.grow(s.positions[s.triangles[t][k]]);
  ASSERT_FALSE(s.cameras.empty());
  ASSERT_FALSE(s.lights.empty());
  const Camera& c = s.cameras[0];
  EXPECT_EQ(c.width, 1280);
  EXPECT_EQ(c.height, 720);
  const Light& l = s.lights[0];
  EXPECT_EQ(l.type, LightType::Spot);
  EXPECT_GT(l.radius, 0.0f);
  const glm::mat4 viewProjection = c.projection(0.1f, 1000.0f) * c.view();
  for (int i = 0; i < 8; ++i) {
    const glm::vec3 corner(i & 1 ? model.max.x : model.min.x, i & 2 ? model.max.y : model.min.y,
                           i & 4 ? model.max.z : model.min.z);
    const glm::vec4 clip = viewProjection * glm::vec4(corner, 1);
    EXPECT_LT(std::max(std::abs(clip.x), std::abs(clip.y)), clip.w) << "corner " << i << " is outside the image";
    const float angle = glm::degrees(std::acos(glm::dot(glm::normalize(corner - l.position), l.axis())));
    EXPECT_LT(angle, l.fovDeg / 2) << "corner " << i << " is outside the light's cone";
  }
}

INSTANTIATE_TEST_SUITE_P(SceneFile, SceneFileBundled,
                         ::testing::Values("default.json", "lantern.json", "suzanne.json", "milk-truck.json"),
                         [](const auto& test_info) {
                           std::string n = test_info.param.substr(0, test_info.param.find('.'));
                           std::replace(n.begin(), n.end(), '-', '_');
                           return n;
                         });

TEST(SceneFileDefault, IsTheAntiqueCameraOnAGround) {
  const Scene s = loadSceneFile(test::bundledScene("default.json"));
  EXPECT_EQ(s.triangleCount(), 20066u + 2u);
  EXPECT_NEAR(s.bounds().min.y, -0.000806f, 1e-6f);  // the ground sits at the model's lowest point
}

}  // namespace scene_file_test
}  // namespace penumbra
