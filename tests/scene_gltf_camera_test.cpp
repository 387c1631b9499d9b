// glTF cameras: import under transformed nodes (a known world point lands on the expected pixel, for a perspective
// and an orthographic camera), names, image size from the aspect ratio, gltf:INDEX|NAME selection in files and
// scene files, and clear errors for malformed camera JSON.
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "host/views/views.h"
#include "host/scene/gltf_loader.h"
#include "host/scene/scene_file.h"
#include "tests/scene_test_util.h"
#include "tests/support/gltf_builder.h"
#include "tests/support/temp_dir.h"

namespace penumbra {
namespace scene_gltf_camera_test {

namespace fs = std::filesystem;
using test::GltfBuilder;
using test::throwsWith;
using Json = nlohmann::json;

constexpr float kPoseTolerance = 1e-5f;   // float round-off of a composed node transform on unit-sized inputs
constexpr float kPixelTolerance = 1e-2f;  // of a projected point, in pixels (float matrices over ~1000 pixels)

// Where `p` lands in the camera's image: pixel coordinates with (0, 0) the bottom-left corner (the G-buffer's
// row order), from the same matrices the G-buffer is drawn with.
glm::vec2 pixelOf(const Camera& camera, const glm::vec3& p, const Bounds& bounds) {
  const RasterView view = cameraView(camera, bounds);
  const glm::vec4 clip = view.projection * view.view * glm::vec4(p, 1.0f);
  const glm::vec2 ndc = glm::vec2(clip) / clip.w;
  return (ndc * 0.5f + 0.5f) * glm::vec2(camera.width, camera.height);
}

class GltfCameras : public ::testing::Test {
 protected:

  static GltfBuilder ground() {
    std::vector<glm::vec3> soup;
    test::addQuadY(soup, 0.0f, 10.0f);
    return GltfBuilder(soup);
  }
  std::string write(const GltfBuilder& b, const std::string& name = "cams") const { return b.write(dir_, name); }

  test::TempDir scratch_{"penumbra_gltf_camera_test"};  // removed with the fixture
  const fs::path dir_ = scratch_.path();
};

// Parent: T (2, 3, 4), R 90 deg about +Y, S 2; child: T (0, 0, 1). The lens (local -Z) then looks down world -X,
// its right (local +X) is world -Z, its up +Y, and the eye sits at (2, 3, 4) + 2 R (0, 0, 1) = (4, 3, 4).
TEST_F(GltfCameras, PerspectiveUnderTransformedNodeProjectsKnownPoint) {
  GltfBuilder b = ground();
  const double s = std::sqrt(0.5);
  const int cam = b.addCamera({{"type", "perspective"},
                               {"name", "Main"},
                               {"perspective", {{"yfov", 0.8}, {"aspectRatio", 1.5}, {"znear", 0.1}, {"zfar", 100}}}});
  const int child = b.addNode({{"camera", cam}, {"translation", {0, 0, 1}}}, false);
  b.addNode({{"translation", {2, 3, 4}}, {"rotation", {0, s, 0, s}}, {"scale", {2, 2, 2}}, {"children", {child}}});
  const Scene scene = loadGltf(write(b));
  ASSERT_EQ(scene.cameras.size(), 1u);
  const Camera& c = scene.cameras.front();
  EXPECT_EQ(c.name, "Main");
  EXPECT_EQ(c.gltfIndex, 0);
  EXPECT_FALSE(c.orthographic());
  EXPECT_EQ(c.width, 1080);  // 720 high at aspectRatio 1.5
  EXPECT_EQ(c.height, 720);
  EXPECT_NEAR(glm::distance(c.eye, glm::vec3(4, 3, 4)), 0.0f, kPoseTolerance);
  EXPECT_NEAR(glm::distance(c.forward(), glm::vec3(-1, 0, 0)), 0.0f, kPoseTolerance);
  EXPECT_NEAR(c.fovYDeg, glm::degrees(0.8f), 1e-4f);
  EXPECT_FLOAT_EQ(c.clipNear, 0.1f);
  EXPECT_FLOAT_EQ(c.clipFar, 100.0f);
  // 5 ahead, 1 to the right, 0.5 up: NDC x = 1 / (5 tan(0.4) 1.5), y = 0.5 / (5 tan(0.4)).
  const glm::vec3 p = c.eye + glm::vec3(-5, 0.5f, -1);
  const float t = std::tan(0.4f);
  const glm::vec2 expected((1.0f / (5 * t * 1.5f) * 0.5f + 0.5f) * 1080, (0.5f / (5 * t) * 0.5f + 0.5f) * 720);
  const glm::vec2 got = pixelOf(c, p, scene.bounds());
  EXPECT_NEAR(got.x, expected.x, kPixelTolerance);
  EXPECT_NEAR(got.y, expected.y, kPixelTolerance);
}

// Parent: T (1, 10, 2), R -90 deg about +X: the lens looks down -Y, its up is -Z, its right +X. xmag 4, ymag 2.
TEST_F(GltfCameras, OrthographicUnderTransformedNodeProjectsKnownPoint) {
  GltfBuilder b = ground();
  const double s = std::sqrt(0.5);
  const int cam =
      b.addCamera({{"type", "orthographic"}, {"orthographic", {{"xmag", 4}, {"ymag", 2}, {"znear", 0}, {"zfar", 50}}}});
  const int child = b.addNode({{"name", "TopView"}, {"camera", cam}}, false);
  b.addNode({{"translation", {1, 10, 2}}, {"rotation", {-s, 0, 0, s}}, {"children", {child}}});
  const Scene scene = loadGltf(write(b));
  ASSERT_EQ(scene.cameras.size(), 1u);
  const Camera& c = scene.cameras.front();
  EXPECT_EQ(c.name, "TopView");  // the camera has no name: its node's
  EXPECT_TRUE(c.orthographic());
  EXPECT_EQ(c.width, 1440);  // 720 high at xmag / ymag = 2
  EXPECT_EQ(c.height, 720);
  EXPECT_FLOAT_EQ(c.orthoHalfHeight, 2.0f);
  EXPECT_NEAR(glm::distance(c.eye, glm::vec3(1, 10, 2)), 0.0f, kPoseTolerance);
  EXPECT_NEAR(glm::distance(c.forward(), glm::vec3(0, -1, 0)), 0.0f, kPoseTolerance);
  // Any depth: 2 right (half of xmag: NDC 0.5) and 1 up (-Z; half of ymag: NDC 0.5).
  for (float depth : {3.0f, 9.0f}) {
    const glm::vec2 got = pixelOf(c, c.eye + glm::vec3(2, -depth, -1), scene.bounds());
    EXPECT_NEAR(got.x, 0.75f * 1440, kPixelTolerance);
    EXPECT_NEAR(got.y, 0.75f * 720, kPixelTolerance);
  }
  // --size with another aspect keeps ymag and widens the view: x at NDC 2 / (2 * 1) = 1 for a square image.
  Camera square = c;
  square.width = square.height = 100;
  EXPECT_NEAR(pixelOf(square, c.eye + glm::vec3(2, -3, -1), scene.bounds()).x, 100.0f, kPixelTolerance);
}

// A near plane beyond the whole scene clips it all, zfar or not (without zfar it used to be ignored).
TEST_F(GltfCameras, NearPlaneBeyondTheSceneWithoutFarClipsEverything) {
  Camera camera;
  camera.eye = {0, 1, 5}, camera.target = {0, 0, 0};
  camera.clipNear = 1e6f, camera.clipFar = INFINITY;
  const Bounds scene{glm::vec3(-10, 0, -10), glm::vec3(10, 0, 10)};
  const RasterView view = cameraView(camera, scene);
  EXPECT_EQ(view.projection, camera.projection(1e6f, 2e6f));
  const glm::vec4 clip = view.projection * view.view * glm::vec4(0, 0, 0, 1);
  EXPECT_LT(clip.z, -clip.w);  // in front of the near plane: clipped
}

TEST_F(GltfCameras, NamesOrderAndSelection) {
  GltfBuilder b = ground();
  const Json persp = {{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.1}}}};
  Json named = persp;
  named["name"] = "Main";
  const int c0 = b.addCamera(named), c1 = b.addCamera(persp), c2 = b.addCamera(persp);
  b.addNode({{"camera", c0}, {"translation", {0, 1, 5}}});
  b.addNode({{"name", "Side"}, {"camera", c1}, {"translation", {5, 1, 0}}});
  b.addNode({{"camera", c2}, {"translation", {0, 5, 0}}});
  const Scene scene = loadGltf(write(b));
  ASSERT_EQ(scene.cameras.size(), 3u);
  EXPECT_EQ(scene.cameras[0].name, "Main");
  EXPECT_EQ(scene.cameras[1].name, "Side");
  EXPECT_EQ(scene.cameras[2].name, "camera 2");
  EXPECT_EQ(scene.cameras[0].width, 1280);            // no aspectRatio: the default viewport
  EXPECT_TRUE(std::isinf(scene.cameras[0].clipFar));  // no zfar: no far clip
  EXPECT_EQ(scene.cameras[1].label(), "gltf:1 \"Side\" (perspective)");
  EXPECT_EQ(findGltfCamera(scene, "Side").gltfIndex, 1);
  EXPECT_EQ(findGltfCamera(scene, "2").name, "camera 2");
  EXPECT_EQ(findGltfCamera(scene, "camera 2").gltfIndex, 2);
  EXPECT_TRUE(throwsWith<std::invalid_argument>([&] { findGltfCamera(scene, "3"); },
                                                {"no glTF camera \"3\"", "0 \"Main\"", "2 \"camera 2\""}));
  EXPECT_TRUE(throwsWith<std::invalid_argument>([&] { findGltfCamera(scene, "Nope"); }, {"\"Nope\"", "1 \"Side\""}));
  Scene none;
  EXPECT_TRUE(throwsWith<std::invalid_argument>([&] { findGltfCamera(none, "0"); }, {"has no glTF cameras"}));
}

TEST_F(GltfCameras, CamerasOutsideTheDefaultSceneAreNotImported) {
  GltfBuilder b = ground();
  const int cam = b.addCamera({{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.1}}}});
  b.addNode({{"camera", cam}}, false);  // in no scene
  EXPECT_TRUE(loadGltf(write(b)).cameras.empty());
}

struct BadCamera {
  Json camera;
  std::vector<std::string> parts;
};

TEST_F(GltfCameras, MalformedCamerasAreRefusedNamingTheElement) {
  const std::vector<BadCamera> cases = {
      {{{"perspective", {{"yfov", 0.5}, {"znear", 0.1}}}}, {"/cameras/0/type", "missing"}},
      {{{"type", "fisheye"}}, {"/cameras/0/type", "\"perspective\" or \"orthographic\""}},
      {{{"type", "perspective"}}, {"/cameras/0/perspective", "missing"}},
      {{{"type", "perspective"}, {"perspective", {{"znear", 0.1}}}}, {"/cameras/0/perspective/yfov", "missing"}},
      {{{"type", "perspective"}, {"perspective", {{"yfov", -1}, {"znear", 0.1}}}},
       {"/cameras/0/perspective/yfov", "> 0"}},
      {{{"type", "perspective"}, {"perspective", {{"yfov", 3.5}, {"znear", 0.1}}}},
       {"/cameras/0/perspective/yfov", "pi"}},
      {{{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0}}}},
       {"/cameras/0/perspective/znear", "> 0"}},
      {{{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 1}, {"zfar", 0.5}}}},
       {"/cameras/0/perspective/zfar", "not beyond znear"}},
      {{{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 1}, {"aspectRatio", "wide"}}}},
       {"/cameras/0/perspective/aspectRatio", "finite number"}},
      {{{"type", "orthographic"}, {"orthographic", {{"xmag", 0}, {"ymag", 1}, {"znear", 0}, {"zfar", 1}}}},
       {"/cameras/0/orthographic/xmag", "a finite non-zero number"}},
      {{{"type", "orthographic"}, {"orthographic", {{"xmag", 1}, {"ymag", 1}, {"znear", 0}}}},
       {"/cameras/0/orthographic/zfar", "missing"}},
      {{{"type", "orthographic"}, {"orthographic", {{"xmag", 1}, {"ymag", 1}, {"znear", -1}, {"zfar", 1}}}},
       {"/cameras/0/orthographic/znear", ">= 0"}},
  };
  for (const BadCamera& bad : cases) {
    GltfBuilder b = ground();
    b.addCamera(bad.camera);
    b.addNode({{"camera", 0}});
    std::vector<std::string> parts = bad.parts;
    parts.push_back("bad.gltf");
    EXPECT_TRUE(throwsWith([&] { loadGltf(write(b, "bad")); }, parts)) << bad.camera.dump();
  }
}

// Sec. 5.14: a negative magnification SHOULD NOT be used but is valid (the validator accepts it): drawn unmirrored,
// with a warning.
TEST_F(GltfCameras, NegativeMagnificationIsDrawnUnmirroredWithAWarning) {
  GltfBuilder b = ground();
  const int cam = b.addCamera(
      {{"type", "orthographic"}, {"orthographic", {{"xmag", 4}, {"ymag", -2}, {"znear", 0}, {"zfar", 50}}}});
  b.addNode({{"translation", {0, 10, 0}}, {"camera", cam}});
  test::CapturingOptions capture;
  const Scene scene = loadGltf(write(b), capture.options);
  ASSERT_EQ(scene.cameras.size(), 1u);
  EXPECT_FLOAT_EQ(scene.cameras.front().orthoHalfHeight, 2.0f);
  EXPECT_EQ(scene.cameras.front().width, 1440);
  ASSERT_EQ(capture.warnings.size(), 1u);
  EXPECT_NE(capture.warnings[0].find("camera 0: negative xmag or ymag (4, -2): drawn unmirrored"), std::string::npos)
      << capture.warnings[0];
}

TEST_F(GltfCameras, BadCameraNodesAreRefused) {
  GltfBuilder b = ground();
  b.addCamera({{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.1}}}});
  b.addNode({{"camera", 3}});
  EXPECT_TRUE(throwsWith([&] { loadGltf(write(b, "range")); }, {"range.gltf", "/nodes/1/camera", "no element 3"}));
  GltfBuilder z = ground();
  z.addCamera({{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.1}}}});
  z.addNode({{"camera", 0}, {"scale", {0, 0, 0}}});
  EXPECT_TRUE(throwsWith([&] { loadGltf(write(z, "zero")); }, {"zero.gltf", "node 1", "degenerate"}));
}

TEST_F(GltfCameras, SceneFileNamesAModelCameraPlacedWithTheModel) {
  GltfBuilder b = ground();
  const Json persp = {{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.1}}}};
  Json named = persp;
  named["name"] = "Main";
  b.addNode({{"camera", b.addCamera(persp)}, {"translation", {0, 1, 5}}});
  b.addNode({{"camera", b.addCamera(named)}, {"translation", {0, 2, 5}}});
  write(b, "model");
  auto load = [&](const std::string& camera) {
    std::ofstream(dir_ / "scene.json") << R"({"models": [{"path": "model.gltf", "translation": [10, 0, 0]}])" + camera +
                                              "}";
    return loadSceneFile((dir_ / "scene.json").string());
  };
  const Scene byDefault = load("");
  ASSERT_EQ(byDefault.cameras.size(), 2u);
  EXPECT_NEAR(glm::distance(byDefault.cameras[0].eye, glm::vec3(10, 1, 5)), 0.0f, kPoseTolerance);  // placed
  const Scene chosen = load(R"(, "camera": "gltf:Main")");
  ASSERT_EQ(chosen.cameras.size(), 2u);  // the chosen one first, the other behind it
  EXPECT_EQ(chosen.cameras[0].name, "Main");
  EXPECT_NEAR(glm::distance(chosen.cameras[0].eye, glm::vec3(10, 2, 5)), 0.0f, kPoseTolerance);
  EXPECT_EQ(chosen.cameras[1].gltfIndex, 0);
  const Scene explicitCamera = load(R"(, "camera": {"eye": [0, 9, 9], "target": [0, 0, 0]})");
  ASSERT_EQ(explicitCamera.cameras.size(), 3u);  // the scene file's first, then the model's for gltf:
  EXPECT_EQ(explicitCamera.cameras[0].gltfIndex, -1);
  EXPECT_TRUE(throwsWith([&] { load(R"(, "camera": "gltf:Nope")"); }, {"scene.json", "/camera", "\"Nope\"", "Main"}));
  EXPECT_TRUE(throwsWith([&] { load(R"(, "camera": "front")"); }, {"scene.json", "/camera", "gltf:INDEX|NAME"}));
}

TEST_F(GltfCameras, AppendRenumbersGltfIndices) {
  GltfBuilder b = ground();
  b.addNode({{"camera", b.addCamera({{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.1}}}})}});
  const Scene one = loadGltf(write(b));
  Scene both = one;
  both.append(one);
  ASSERT_EQ(both.cameras.size(), 2u);
  EXPECT_EQ(both.cameras[1].gltfIndex, 1);
}

}  // namespace scene_gltf_camera_test
}  // namespace penumbra
