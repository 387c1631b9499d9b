// glTF animation at --time (LoadOptions::time): translation, rotation and scale channels with STEP, LINEAR and
// CUBICSPLINE samplers against the glTF 2.0 appendix C formulas evaluated here in double precision, clamping outside
// the keys, --animation selection, morph targets (static and animated weights), skins (joint matrices, the skinned
// node's own transform ignored), cameras and lights riding animated nodes, and clear errors for malformed data.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <glm/gtc/quaternion.hpp>

#include "host/scene/gltf_loader.h"
#include "tests/scene_test_util.h"
#include "tests/support/gltf_builder.h"
#include "tests/support/temp_dir.h"

namespace penumbra {
namespace scene_gltf_animation_test {

using test::GltfBuilder;
using test::throwsWith;
using Json = nlohmann::json;

constexpr float kTolerance = 1e-5f;  // float storage of positions of unit size after a double-precision pose

// One triangle with a corner at the origin, as mesh 0 on node 0.
std::vector<glm::vec3> triangle() { return {{0, 0, 0}, {1, 0, 0}, {0, 0, -1}}; }

class GltfAnimation : public ::testing::Test {
 protected:
  // Adds animation 0 (or appends to the last one) with one channel on `node`'s `path`.
  static void animate(GltfBuilder& b, int node, const std::string& path, const std::vector<double>& times,
                      const std::vector<double>& values, const std::string& type, const std::string& interpolation,
                      const std::string& name = "", int componentType = 5126, bool normalized = false) {
    const int input = b.addAccessor(times, "SCALAR"), output = b.addAccessor(values, type, componentType, normalized);
    Json& doc = b.doc();
    if (!doc.contains("animations") || !name.empty())
      doc["animations"].push_back({{"name", name}, {"channels", Json::array()}, {"samplers", Json::array()}});
    Json& a = doc["animations"].back();
    a["samplers"].push_back({{"input", input}, {"output", output}, {"interpolation", interpolation}});
    a["channels"].push_back({{"sampler", a["samplers"].size() - 1}, {"target", {{"node", node}, {"path", path}}}});
  }

  // Skins mesh 0's primitive (node 0) with four joints and weights per vertex (unsigned-byte joints) and skin 0 of
  // the nodes `joints`.
  static void skin(GltfBuilder& b, const std::vector<double>& joints, const std::vector<double>& weights,
                   const Json& jointNodes) {
    const int jointAccessor = b.addAccessor(joints, "VEC4", 5121), weightAccessor = b.addAccessor(weights, "VEC4");
    b.doc()["meshes"][0]["primitives"][0]["attributes"]["JOINTS_0"] = jointAccessor;
    b.doc()["meshes"][0]["primitives"][0]["attributes"]["WEIGHTS_0"] = weightAccessor;
    b.doc()["skins"] = {{{"joints", jointNodes}}};
    b.doc()["nodes"][0]["skin"] = 0;
  }

  Scene load(const GltfBuilder& b, std::optional<double> time, const std::string& animation = "") {
    test::CapturingOptions capture;
    capture.options.time = time;
    capture.options.animation = animation;
    Scene s = loadGltf(b.write(dir_, "anim"), capture.options);
    warnings_ = capture.warnings;
    return s;
  }

  test::TempDir scratch_{"penumbra_gltf_animation_test"};
  const std::filesystem::path dir_ = scratch_.path();
  std::vector<std::string> warnings_;
};

void expectNear(const glm::vec3& got, const glm::dvec3& want, const std::string& what) {
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], kTolerance) << what << " component " << c;
}

TEST_F(GltfAnimation, LinearAndStepTranslationClampOutsideTheKeys) {
  for (const char* interpolation : {"LINEAR", "STEP"}) {
    GltfBuilder b(triangle());
    b.doc()["nodes"][0]["translation"] = {9, 9, 9};  // replaced by the animation at any --time
    animate(b, 0, "translation", {1, 3}, {0, 0, 0, 4, 2, 0}, "VEC3", interpolation);
    const bool step = std::string(interpolation) == "STEP";
    expectNear(load(b, std::nullopt).positions[0], {9, 9, 9}, "static pose");
    expectNear(load(b, 2.0).positions[0], step ? glm::dvec3(0, 0, 0) : glm::dvec3(2, 1, 0), interpolation);
    expectNear(load(b, 2.5).positions[1], step ? glm::dvec3(1, 0, 0) : glm::dvec3(4, 1.5, 0), interpolation);
    expectNear(load(b, -5.0).positions[0], {0, 0, 0}, "before the first key");
    expectNear(load(b, 3.0).positions[0], {4, 2, 0}, "at the last key");
    expectNear(load(b, 50.0).positions[0], {4, 2, 0}, "after the last key");
  }
}

TEST_F(GltfAnimation, RotationSlerpsTheShorterArcFromNormalizedShorts) {
  GltfBuilder b(triangle());
  // 0 and 90 degrees about +Y as normalized SHORT quaternions (x, y, z, w), the second negated: the same rotation,
  // so the shorter arc runs from 0 to 90 degrees, not the long way round.
  const double s = std::sqrt(0.5) * 32767.0;
  animate(b, 0, "rotation", {0, 1}, {0, 0, 0, 32767, 0, -std::round(s), 0, -std::round(s)}, "VEC4", "LINEAR", "", 5122,
          true);
  const Scene scene = load(b, 0.5);
  // (1, 0, 0) turned 45 degrees about +Y: (cos 45, 0, -sin 45).
  const double c = std::cos(glm::radians(45.0));
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(scene.positions[1][k], (glm::dvec3(c, 0, -c))[k], 2e-4) << k;  // 1/32767
  EXPECT_TRUE(test::wellFormed(scene));
}

TEST_F(GltfAnimation, CubicSplineScaleFollowsHermiteWithTangentsTimesTheKeyInterval) {
  GltfBuilder b(triangle());
  // Keys at t = 0 and 2: (in-tangent, value, out-tangent) per key, scale on x only.
  const std::vector<double> out = {0, 0, 0, 1, 1, 1, 3, 0, 0, /* key 1 */ -1, 0, 0, 2, 1, 1, 0, 0, 0};
  animate(b, 0, "scale", {0, 2}, out, "VEC3", "CUBICSPLINE");
  for (double t : {0.0, 0.5, 1.0, 1.7, 2.0}) {
    const double d = 2.0, u = t / d, u2 = u * u, u3 = u2 * u;
    const double sx = (2 * u3 - 3 * u2 + 1) * 1 + d * (u3 - 2 * u2 + u) * 3 + (-2 * u3 + 3 * u2) * 2 +
                      d * (u3 - u2) * -1;  // appendix C with v0 = 1, b0 = 3, v1 = 2, a1 = -1
    expectNear(load(b, t).positions[1], {sx, 0, 0}, "t = " + std::to_string(t));
  }
}

TEST_F(GltfAnimation, AnimationIsSelectedByIndexOrNameAndLaterChannelsWin) {
  GltfBuilder b(triangle());
  animate(b, 0, "translation", {0, 1}, {1, 0, 0, 1, 0, 0}, "VEC3", "LINEAR", "Right");
  animate(b, 0, "translation", {0, 1}, {0, 5, 0, 0, 5, 0}, "VEC3", "LINEAR", "Up");
  expectNear(load(b, 0.5).positions[0], {0, 5, 0}, "every animation: the later one wins");
  expectNear(load(b, 0.5, "Right").positions[0], {1, 0, 0}, "by name");
  expectNear(load(b, 0.5, "1").positions[0], {0, 5, 0}, "by index");
  EXPECT_TRUE(throwsWith([&] { load(b, 0.5, "Walk"); }, {"--animation Walk", "0 \"Right\"", "1 \"Up\""}));
}

TEST_F(GltfAnimation, MorphTargetsAddWeightedDisplacements) {
  GltfBuilder b(triangle());
  const int up = b.addAccessor({0, 1, 0, 0, 1, 0, 0, 1, 0}, "VEC3"),
            side = b.addAccessor({2, 0, 0, 2, 0, 0, 2, 0, 0}, "VEC3");
  b.doc()["meshes"][0]["primitives"][0]["targets"] = {{{"POSITION", up}}, {{"POSITION", side}}};
  b.doc()["meshes"][0]["weights"] = {0.5, 0.0};
  expectNear(load(b, std::nullopt).positions[0], {0, 0.5, 0}, "the mesh's default weights");
  b.doc()["nodes"][0]["weights"] = {0.0, 0.25};
  expectNear(load(b, std::nullopt).positions[0], {0.5, 0, 0}, "the node's weights replace the mesh's");
  animate(b, 0, "weights", {0, 1}, {0, 0, 1, 1}, "SCALAR", "LINEAR");  // two targets per key
  expectNear(load(b, 0.5).positions[2], {1, 0.5, -1}, "animated weights");
  EXPECT_TRUE(test::wellFormed(load(b, 0.5)));
}

TEST_F(GltfAnimation, SkinsMoveVerticesByTheirJointsAndIgnoreTheSkinnedNodesTransform) {
  GltfBuilder b(triangle());
  const int root = b.addNode({{"name", "root"}, {"children", {2}}});
  b.addNode({{"name", "tip"}, {"translation", {0, 0, 0}}}, false);
  // Vertex 0 on the root joint, vertices 1 and 2 half on each.
  skin(b, {0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0}, {1, 0, 0, 0, 0.5, 0.5, 0, 0, 0.5, 0.5, 0, 0}, {root, 2});
  b.doc()["nodes"][0]["translation"] = {100, 100, 100};  // must not apply (sec. 3.7.3.3)
  expectNear(load(b, std::nullopt).positions[1], {1, 0, 0}, "bind pose");
  animate(b, 2, "translation", {0, 1}, {0, 0, 0, 0, 4, 0}, "VEC3", "LINEAR");
  const Scene s = load(b, 1.0);
  expectNear(s.positions[0], {0, 0, 0}, "on the still root");
  expectNear(s.positions[1], {1, 2, 0}, "half on the raised tip");
  expectNear(s.positions[2], {0, 2, -1}, "half on the raised tip");
  EXPECT_TRUE(test::wellFormed(s));
}

TEST_F(GltfAnimation, CamerasAndLightsRideAnimatedNodes) {
  GltfBuilder b(triangle());
  b.doc()["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.1}}}}};
  b.doc()["extensionsUsed"] = {"KHR_lights_punctual"};
  b.doc()["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "directional"}, {"name", "Sun"}}};
  const int cam = b.addNode({{"camera", 0}, {"translation", {0, 1, 5}}});
  const int sun = b.addNode({{"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  animate(b, cam, "translation", {0, 1}, {0, 1, 5, 0, 1, 7}, "VEC3", "LINEAR");
  const double s = std::sqrt(0.5);  // the sun turned 90 degrees about +X: from shining along -Z to along +Y
  animate(b, sun, "rotation", {0, 1}, {0, 0, 0, 1, s, 0, 0, s}, "VEC4", "LINEAR");
  const Scene scene = load(b, 1.0);
  ASSERT_EQ(scene.cameras.size(), 1u);
  expectNear(scene.cameras[0].eye, {0, 1, 7}, "camera eye");
  ASSERT_EQ(scene.lights.size(), 1u);
  expectNear(scene.lights[0].direction, {0, 1, 0}, "sun direction");
}

TEST_F(GltfAnimation, MalformedAnimationsAndSkinsGiveClearErrors) {
  {
    GltfBuilder b(triangle());
    animate(b, 0, "translation", {1, 0}, {0, 0, 0, 1, 1, 1}, "VEC3", "LINEAR");
    EXPECT_TRUE(throwsWith([&] { load(b, 0.5); }, {"animation 0 channel 0", "does not increase"}));
  }
  {  // sec. 5.8: strictly increasing
    GltfBuilder b(triangle());
    animate(b, 0, "translation", {0, 0}, {0, 0, 0, 1, 1, 1}, "VEC3", "LINEAR");
    EXPECT_TRUE(throwsWith([&] { load(b, 0.5); },
                           {"animation 0 channel 0: input time 1 (0) is not finite or does not increase"}));
  }
  {  // the structure is checked without --time too
    GltfBuilder b(triangle());
    animate(b, 0, "translation", {0, 1}, {0, 0, 0, 1, 1, 1}, "VEC3", "LINEAR");
    b.doc()["animations"][0]["channels"][0]["sampler"] = 3;
    EXPECT_TRUE(throwsWith([&] { load(b, std::nullopt); },
                           {"/animations/0/channels/0/sampler", "no sampler 3 in this animation (it has 1)"}));
    b.doc()["animations"][0]["channels"][0]["sampler"] = 0;
    b.doc()["animations"][0]["samplers"][0]["output"] = 99;
    EXPECT_TRUE(
        throwsWith([&] { load(b, std::nullopt); }, {"/animations/0/samplers/0/output", "no element 99 in accessors"}));
  }
  {
    GltfBuilder b(triangle());
    animate(b, 0, "translation", {0, 1}, {0, 0, 0}, "VEC3", "LINEAR");
    EXPECT_TRUE(throwsWith([&] { load(b, 0.5); }, {"output has 3 numbers", "need 6"}));
  }
  {
    GltfBuilder b(triangle());
    animate(b, 0, "translation", {0, 1}, {0, 0, 0, 1, std::nan(""), 1}, "VEC3", "LINEAR");
    EXPECT_TRUE(throwsWith([&] { load(b, 0.5); }, {"animation 0 channel 0: output key 1 of 'translation' holds nan"}));
  }
  {
    GltfBuilder b(triangle());
    animate(b, 0, "weights", {0, 1}, {0, 1}, "SCALAR", "LINEAR");
    EXPECT_TRUE(throwsWith([&] { load(b, 0.5); }, {"no morph targets"}));
  }
  {
    GltfBuilder b(triangle());
    animate(b, 0, "translation", {0, 1}, {0, 0, 0, 1, 1, 1}, "VEC3", "BEZIER");
    EXPECT_TRUE(throwsWith([&] { load(b, 0.5); }, {"unknown interpolation 'BEZIER'"}));
  }
  {
    GltfBuilder b(triangle());
    b.doc()["nodes"][0]["matrix"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    animate(b, 0, "translation", {0, 1}, {0, 0, 0, 1, 1, 1}, "VEC3", "LINEAR");
    EXPECT_TRUE(throwsWith([&] { load(b, 0.5); }, {"has a matrix"}));
    EXPECT_NO_THROW(load(b, std::nullopt));  // without --time the animation is not read
  }
  {
    GltfBuilder b(triangle());
    skin(b, {0, 0, 0, 0, 3, 0, 0, 0, 0, 0, 0, 0}, {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0}, {0});
    EXPECT_TRUE(throwsWith([&] { load(b, std::nullopt); }, {"vertex 1", "joint 3 out of range"}));
  }
  {  // sec. 3.7.3.3: weights sum to one; a vertex whose weights are all zero is refused
    GltfBuilder b(triangle());
    skin(b, {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0}, {1, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0}, {0});
    EXPECT_TRUE(throwsWith([&] { load(b, std::nullopt); }, {"vertex 1: its skin weights sum to 0"}));
  }
  {
    GltfBuilder b(triangle());
    const int target = b.addAccessor({0, 1, 0}, "VEC3");  // one element for three vertices
    b.doc()["meshes"][0]["primitives"][0]["targets"] = {{{"POSITION", target}}};
    b.doc()["meshes"][0]["weights"] = {1.0};
    EXPECT_TRUE(throwsWith([&] { load(b, std::nullopt); }, {"target 0", "POSITION has 1 elements"}));
  }
}

TEST_F(GltfAnimation, TimeWithoutAnimationsWarnsAndKeepsTheStaticPose) {
  GltfBuilder b(triangle());
  b.doc()["nodes"][0]["translation"] = {1, 2, 3};
  expectNear(load(b, 4.0).positions[0], {1, 2, 3}, "static pose");
  ASSERT_EQ(warnings_.size(), 1u);
  EXPECT_NE(warnings_[0].find("no animations"), std::string::npos) << warnings_[0];
}

// Real files from Debian's assimp-testmodels. The glTF tutorial's simple skin: a strip x in [0, 1], y in [0, 2];
// joint 1 (node 1) at (0, 1, 0), joint 2 (node 2) its child at the same place, both with the inverse bind matrix
// T(-0.5, -1, 0); joint 2 turns about +Z, 90 degrees at its key t = 1 s. The bottom edge, on joint 1 alone, moves by
// J1 IBM1 = T(-0.5, 0, 0) to (-0.5, 0, 0) and (0.5, 0, 0); the top edge, on joint 2 alone, by T(0, 1, 0) R90 IBM2
// from (0, 2, 0) and (1, 2, 0) to (-1, 0.5, 0) and (-1, 1.5, 0).
TEST(GltfAnimationFiles, TutorialSimpleSkinBendsItsTopByNinetyDegrees) {
  const std::string path = "/usr/share/assimp/models/glTF2/simple_skin/simple_skin.gltf";
  ASSERT_TRUE(std::filesystem::exists(path)) << path << " is missing: install assimp-testmodels";
  test::CapturingOptions capture;
  capture.options.time = 1.0;
  const Scene s = loadGltf(path, capture.options);
  EXPECT_TRUE(test::wellFormed(s));
  auto has = [&](const glm::vec3& want) {
    return std::any_of(s.positions.begin(), s.positions.end(),
                       [&](const glm::vec3& p) { return glm::length(p - want) < kTolerance; });
  };
  for (const glm::vec3& want :
       {glm::vec3(-0.5f, 0, 0), glm::vec3(0.5f, 0, 0), glm::vec3(-1, 0.5f, 0), glm::vec3(-1, 1.5f, 0)})
    EXPECT_TRUE(has(want)) << want.x << ", " << want.y << ", " << want.z;
  EXPECT_FALSE(has(glm::vec3(-0.5f, 2, 0))) << "the top edge must have turned";
  EXPECT_TRUE(capture.warnings.empty()) << capture.warnings.front();
}

// Khronos's AnimatedMorphCube: two morph targets animated over time; its shape at a time with non-zero weights
// differs from the static pose, and stays a well-formed surface.
TEST(GltfAnimationFiles, AnimatedMorphCubeChangesShapeOverTime) {
  const std::string path =
      "/usr/share/assimp/models/glTF2/glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf";
  ASSERT_TRUE(std::filesystem::exists(path)) << path << " is missing: install assimp-testmodels";
  test::CapturingOptions still, moving;
  moving.options.time = 1.0;
  const Scene a = loadGltf(path, still.options), b = loadGltf(path, moving.options);
  ASSERT_EQ(a.positions.size(), b.positions.size());
  EXPECT_TRUE(test::wellFormed(b));
  float moved = 0.0f;
  for (size_t i = 0; i < a.positions.size(); ++i) moved = std::max(moved, glm::length(a.positions[i] - b.positions[i]));
  EXPECT_GT(moved, 1e-3f);
}

}  // namespace scene_gltf_animation_test
}  // namespace penumbra
