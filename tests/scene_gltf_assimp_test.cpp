// The glTF 2.0 test files of Debian's assimp-testmodels package: the malformed ones must be refused with a
// clear message, the valid ones must load. Nothing is skipped: a missing package fails the test.
#include <filesystem>

#include <gtest/gtest.h>

#include "host/scene/gltf_loader.h"
#include "scene_test_util.h"

namespace penumbra {
namespace scene_gltf_assimp_test {

const std::string kAssimpDir = "/usr/share/assimp/models/glTF2/";

struct AssimpCase {
  const char* file;
  std::vector<std::string> error;  // empty: the file is valid and must load; else substrings of the error
  size_t triangles = 0;            // for valid files
};

class GltfAssimp : public ::testing::TestWithParam<AssimpCase> {};

TEST_P(GltfAssimp, RefusedOrLoaded) {
  const std::string path = kAssimpDir + GetParam().file;
  ASSERT_TRUE(std::filesystem::exists(path))
      << path << " is missing: install Debian's assimp-testmodels package (apt-get install assimp-testmodels)";
  if (!GetParam().error.empty()) {
    EXPECT_TRUE(test::throwsWith([&] { loadGltf(path, test::CapturingOptions().options); }, GetParam().error));
    return;
  }
  test::CapturingOptions capture;
  const Scene s = loadGltf(path, capture.options);
  EXPECT_EQ(s.triangleCount(), GetParam().triangles);
  EXPECT_TRUE(test::wellFormed(s));
}

using E = std::vector<std::string>;

INSTANTIATE_TEST_SUITE_P(
    Gltf, GltfAssimp,
    ::testing::Values(
        // Malformed.
        AssimpCase{"IndexOutOfRange/IndexOutOfRange.gltf", E{"accessor 0: index 255 out of range (vertex count 24)"}},
        AssimpCase{"IndexOutOfRange/AllIndicesOutOfRange.gltf",
                   E{"accessor 0: index", "out of range (vertex count 24)"}},
        AssimpCase{"MissingBin/BoxTextured.gltf", E{"BoxTextured0.bin", "file not found"}},
        AssimpCase{"RecursiveNodes/RecursiveNodes.gltf", E{"cycle", "node 1 -> node 0 -> node 1"}},
        AssimpCase{"BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb", E{"accessor 2: POSITION 0 is not finite"}},
        AssimpCase{"IncorrectVertexArrays/Cube.gltf", E{"mesh 1 primitive 0", "35 vertices is not a multiple of 3"}},
        AssimpCase{"wrongTypes/badArray.gltf", E{"/meshes/0/primitives", "expected a non-empty array"}},
        AssimpCase{"wrongTypes/badExtension.gltf", E{"extensions/KHR_texture_transform", "expected an object"}},
        AssimpCase{"wrongTypes/badNumber.gltf", E{"/materials/0/normalTexture/scale", "expected a finite number"}},
        AssimpCase{"wrongTypes/badObject.gltf", E{"/materials/0/pbrMetallicRoughness", "expected an object"}},
        AssimpCase{"wrongTypes/badString.gltf", E{"/scenes/0/name", "expected a string"}},
        AssimpCase{"wrongTypes/badUint.gltf", E{"baseColorTexture/index", "non-negative integer"}},
        AssimpCase{"SchemaFailures/sceneWrongType.gltf", E{"/scene", "\"hello\""}},
        AssimpCase{"TestNoRootNode/NoScene.gltf", E{"/scene", "no element 0 in scenes"}},
        AssimpCase{"TestNoRootNode/SceneWithoutNodes.gltf", E{"no triangles"}},
        AssimpCase{"draco/2CylinderEngine.gltf", E{"KHR_draco_mesh_compression is required but not supported"}},
        AssimpCase{"BoxTextured-glTF-techniqueWebGL/BoxTextured.gltf", E{"KHR_technique_webgl is required"}},
        AssimpCase{"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_00.gltf", E{"no triangles"}},
        AssimpCase{"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_08.gltf", E{"no triangles"}},
        // Valid (bad normals are repaired with a warning; skins and morph targets are ignored).
        AssimpCase{"BoxBadNormals-glTF-Binary/BoxBadNormals.glb", {}, 12},
        AssimpCase{"BoxTextured-glTF/BoxTextured.gltf", {}, 12},
        AssimpCase{"BoxTextured-glTF-Binary/BoxTextured.glb", {}, 12},
        AssimpCase{"BoxTextured-glTF-Embedded/BoxTextured.gltf", {}, 12},
        AssimpCase{"BoxTextured-glTF-pbrSpecularGlossiness/BoxTextured.gltf", {}, 12},
        AssimpCase{"BoxTexcoords-glTF/boxTexcoords.gltf", {}, 12},
        AssimpCase{"2CylinderEngine-glTF-Binary/2CylinderEngine.glb", {}, 121496},
        AssimpCase{"ClearCoat-glTF/ClearCoatTest.gltf", {}, 37116}, AssimpCase{"cameras/Cameras.gltf", {}, 2},
        AssimpCase{"glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf", {}, 12},
        AssimpCase{"issue_3269/texcoord_crash.gltf", {}, 10}, AssimpCase{"simple_skin/simple_skin.gltf", {}, 8},
        AssimpCase{"textureTransform/TextureTransformTest.gltf", {}, 24}),
    [](const auto& test_info) {
      std::string name = test_info.param.file;
      for (char& c : name) c = std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
      return name;
    });

// Triangle strips and fans (with and without indices) become the same two counter-clockwise triangles
// as the plain lists: a unit quad in z = 0 facing +Z. Points and lines are skipped with a warning.
class GltfAssimpPrimitiveModes : public ::testing::TestWithParam<int> {};

TEST_P(GltfAssimpPrimitiveModes, TrianglesOrSkipped) {
  const std::string path = kAssimpDir + "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_" +
                           (GetParam() < 10 ? "0" : "") + std::to_string(GetParam()) + ".gltf";
  ASSERT_TRUE(std::filesystem::exists(path)) << path << " is missing: install assimp-testmodels";
  static constexpr bool kTriangles[16] = {0, 0, 0, 0, 1, 1, 1, 0, 0, 0, 0, 1, 1, 1, 1, 1};
  test::CapturingOptions capture;
  if (!kTriangles[GetParam()]) {
    EXPECT_TRUE(test::throwsWith([&] { loadGltf(path, capture.options); }, {"no triangles"}));
    ASSERT_EQ(capture.warnings.size(), 1u);
    EXPECT_NE(capture.warnings[0].find("skipped"), std::string::npos) << capture.warnings[0];
    return;
  }
  const Scene s = loadGltf(path, capture.options);
  ASSERT_EQ(s.triangleCount(), 2u);
  EXPECT_EQ(s.bounds().min, glm::vec3(-0.5f, -0.5f, 0));
  EXPECT_EQ(s.bounds().max, glm::vec3(0.5f, 0.5f, 0));
  for (const glm::vec3& n : s.normals) EXPECT_EQ(n, glm::vec3(0, 0, 1));
  EXPECT_TRUE(test::windingMatchesNormals(s, 0.999f));
}

INSTANTIATE_TEST_SUITE_P(Gltf, GltfAssimpPrimitiveModes, ::testing::Range(0, 16));

}  // namespace scene_gltf_assimp_test
}  // namespace penumbra
