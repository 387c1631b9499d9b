// loadScene dispatch: builtin:NAME, .json, .gltf and .glb (extension case-insensitive), and clear errors
// for unknown kinds of scene and missing files.
#include <filesystem>
#include <unistd.h>

#include <gtest/gtest.h>

#include "host/scene/load.h"
#include "scene_test_util.h"

namespace penumbra {
namespace scene_load_test {

namespace fs = std::filesystem;
using test::throwsWith;

TEST(SceneLoad, DispatchesOnPrefixAndExtension) {
  EXPECT_EQ(loadScene("builtin:box").objectNames, (std::vector<std::string>{"ground", "box"}));
  EXPECT_EQ(loadScene(test::sceneData("triangle.gltf")).triangleCount(), 1u);
  EXPECT_EQ(loadScene(test::sceneData("triangle.glb")).triangleCount(), 1u);
  EXPECT_EQ(loadScene(test::bundledScene("default.json")).triangleCount(), 20068u);
}

TEST(SceneLoad, ExtensionIsCaseInsensitive) {
  const fs::path dir = fs::temp_directory_path() / ("penumbra_scene_load_test_" + std::to_string(getpid()));
  fs::create_directories(dir);
  fs::copy_file(test::sceneData("triangle.glb"), dir / "TRIANGLE.GLB", fs::copy_options::overwrite_existing);
  EXPECT_EQ(loadScene((dir / "TRIANGLE.GLB").string()).triangleCount(), 1u);
  fs::remove_all(dir);
}

TEST(SceneLoad, ClearErrors) {
  EXPECT_TRUE(throwsWith([] { loadScene("scene.obj"); }, {"scene.obj: unknown kind of scene"}));
  EXPECT_TRUE(throwsWith([] { loadScene("noextension"); }, {"noextension: unknown kind of scene"}));
  EXPECT_TRUE(throwsWith([] { loadScene("/no/such/dir/model.glb"); }, {"/no/such/dir/model.glb: file not found"}));
  EXPECT_TRUE(throwsWith([] { loadScene("/no/such/scene.JSON"); }, {"/no/such/scene.JSON: file not found"}));
  EXPECT_TRUE(throwsWith([] { loadScene("builtin:"); }, {"unknown built-in scene"}));
  EXPECT_TRUE(throwsWith([] { loadScene("builtin:nope"); }, {"builtin:nope: unknown built-in scene"}));
}

TEST(SceneLoad, WarningsGoToTheSink) {
  test::CapturingOptions capture;
  const Scene s =
      loadScene("/usr/share/assimp/models/glTF2/BoxBadNormals-glTF-Binary/BoxBadNormals.glb", capture.options);
  EXPECT_EQ(s.triangleCount(), 12u);
  ASSERT_EQ(capture.warnings.size(), 1u) << "install assimp-testmodels if the file is missing";
  EXPECT_NE(capture.warnings[0].find("normals replaced"), std::string::npos) << capture.warnings[0];
}

}  // namespace scene_load_test
}  // namespace penumbra
