// glTF loading of valid files: every bundled model against the triangle counts and world bounds in
// /work/shared/scenes/README.md (instancing flattened), the hand-written transform file (translated,
// rotated, mirrored and nested nodes), flat normals, sparse accessors, files without scenes, and GLB.
#include <map>

#include <gtest/gtest.h>

#include "host/scene/gltf_loader.h"
#include "scene_test_util.h"

namespace penumbra {
namespace scene_gltf_test {

using test::bundledScene;
using test::sceneData;

constexpr float kBoundsTolerance = 1e-5f;    // README bounds are printed with 6 decimals
constexpr float kPositionTolerance = 1e-6f;  // exact transforms of small integers, float round-off only

struct Model {
  const char* file;
  size_t triangles, vertices, objects;
  glm::vec3 min, max;
};

class GltfBundled : public ::testing::TestWithParam<Model> {};

TEST_P(GltfBundled, CountsAndWorldBoundsMatchTheReadme) {
  const Model& m = GetParam();
  test::CapturingOptions capture;
  const Scene s = loadGltf(bundledScene(m.file), capture.options);
  EXPECT_TRUE(capture.warnings.empty()) << capture.warnings.front();
  EXPECT_EQ(s.triangleCount(), m.triangles);
  EXPECT_EQ(s.positions.size(), m.vertices);
  EXPECT_EQ(s.objectNames.size(), m.objects);
  const Bounds b = s.bounds();
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(b.min[k], m.min[k], kBoundsTolerance) << "min axis " << k;
    EXPECT_NEAR(b.max[k], m.max[k], kBoundsTolerance) << "max axis " << k;
  }
  EXPECT_TRUE(test::wellFormed(s));
  EXPECT_TRUE(s.cameras.empty());
  EXPECT_TRUE(s.lights.empty());
}

INSTANTIATE_TEST_SUITE_P(
    Gltf, GltfBundled,
    ::testing::Values(
        Model{"AntiqueCamera.glb",
              20066,
              21178,
              2,
              {-1.625990f, -0.000806f, -1.894955f},
              {0.971454f, 7.208051f, 1.499635f}},
        Model{"Lantern.glb", 5394, 4145, 3, {-3.922445f, 0.183921f, -2.315710f}, {11.568753f, 25.848139f, 2.315710f}},
        Model{"Suzanne.glb", 3936, 11808, 1, {-1.336914f, -0.974609f, -0.800781f}, {1.336914f, 0.950195f, 0.825684f}},
        Model{"CesiumMilkTruck.glb",
              3624,
              3564,
              5,
              {-2.430910f, 0.001452f, -1.396000f},
              {2.438000f, 2.584370f, 1.396000f}}),
    [](const auto& test_info) {
      return std::string(test_info.param.file).substr(0, std::string(test_info.param.file).find('.'));
    });

TEST(GltfBundled, TruckWheelsAreTwoInstancesOfOneMesh) {
  const Scene s = loadGltf(bundledScene("CesiumMilkTruck.glb"));
  std::map<std::string, int> meshUses;  // "mesh/primitive" part of "node/mesh/primitive"
  for (const std::string& name : s.objectNames) ++meshUses[name.substr(name.find('/') + 1)];
  EXPECT_EQ(meshUses["Wheels/0"], 2);
}

TEST(GltfTransforms, TranslatedRotatedMirroredAndNested) {
  const Scene s = loadGltf(sceneData("transforms.gltf"));
  ASSERT_EQ(s.triangleCount(), 4u);
  ASSERT_EQ(s.objectNames,
            (std::vector<std::string>{"translated/tri/0", "rotated/tri/0", "mirrored/tri/0", "child/tri/0"}));
  // The source triangle is (0,0,0), (1,0,0), (0,1,0) with normal +Z.
  const glm::vec3 expected[4][3] = {
      {{10, 0, 0}, {11, 0, 0}, {10, 1, 0}},  // translation (10, 0, 0)
      {{0, 0, 0}, {0, 0, -1}, {0, 1, 0}},    // +90 degrees about +Y: x -> -z
      {{0, 0, 0}, {0, 1, 0}, {-1, 0, 0}},    // scale (-1, 1, 1): x -> -x, winding reversed
      {{0, 5, 2}, {1, 5, 2}, {0, 6, 2}},     // matrix parent (0, 5, 0) * child translation (0, 0, 2)
  };
  const glm::vec3 normals[4] = {{0, 0, 1}, {1, 0, 0}, {0, 0, 1}, {0, 0, 1}};
  for (size_t t = 0; t < 4; ++t) {
    EXPECT_EQ(s.objectIds[t], t);
    for (int k = 0; k < 3; ++k) {
      const glm::vec3 p = s.positions[s.triangles[t][k]], n = s.normals[s.triangles[t][k]];
      EXPECT_NEAR(glm::distance(p, expected[t][k]), 0.0f, kPositionTolerance) << "triangle " << t << " corner " << k;
      EXPECT_NEAR(glm::distance(n, normals[t]), 0.0f, kPositionTolerance) << "triangle " << t << " corner " << k;
    }
  }
  EXPECT_TRUE(test::windingMatchesNormals(s, 0.999f));
  EXPECT_TRUE(test::wellFormed(s));
}

TEST(GltfTransforms, MissingNormalsBecomeFlatNormals) {
  const Scene s = loadGltf(sceneData("no_normals.gltf"));
  ASSERT_EQ(s.triangleCount(), 1u);
  for (const glm::vec3& n : s.normals) EXPECT_EQ(n, glm::vec3(0, 0, 1));
}

TEST(GltfTransforms, SparseAccessorsAreApplied) {
  const Scene s = loadGltf(sceneData("sparse.gltf"));
  ASSERT_EQ(s.positions.size(), 3u);
  EXPECT_EQ(s.positions[2], glm::vec3(0, 3, 0));
  EXPECT_EQ(s.positions[1], glm::vec3(1, 0, 0));
}

TEST(GltfTransforms, WithoutScenesEveryRootNodeIsDrawn) {
  const Scene s = loadGltf(sceneData("no_scene.gltf"));
  EXPECT_EQ(s.triangleCount(), 2u);
  EXPECT_EQ(s.bounds().min.z, -1.0f);
}

TEST(GltfTransforms, GlbAndGltfGiveTheSameScene) {
  const Scene a = loadGltf(sceneData("triangle.gltf")), b = loadGltf(sceneData("triangle.glb"));
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_EQ(a.normals, b.normals);
  EXPECT_EQ(a.triangles, b.triangles);
}

}  // namespace scene_gltf_test
}  // namespace penumbra
