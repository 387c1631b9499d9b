// Camera: the command-line forms (good and bad), the view matrix (including looking straight up and
// down, where the default up vector degenerates), the projection, and describe() round trips.
#include <stdexcept>

#include <gtest/gtest.h>

#include "host/scene/camera.h"
#include "scene_test_util.h"

namespace penumbra {
namespace scene_camera_test {

using test::throwsWith;

constexpr float kMatrixTolerance = 1e-5f;  // float round-off of lookAt/perspective on unit-sized inputs

TEST(CameraParse, EyeTargetAndFov) {
  const Camera c = parseCamera("1,2,3:4,5,6.5:60");
  EXPECT_EQ(c.eye, glm::vec3(1, 2, 3));
  EXPECT_EQ(c.target, glm::vec3(4, 5, 6.5f));
  EXPECT_EQ(c.fovYDeg, 60.0f);
}

TEST(CameraParse, FovIsOptional) {
  const Camera c = parseCamera("-1e1,0,0:0,0,-0.5");
  EXPECT_EQ(c.eye, glm::vec3(-10, 0, 0));
  EXPECT_EQ(c.fovYDeg, Camera{}.fovYDeg);
}

struct BadSpec {
  const char* spec;
  const char* part;  // the message must name it
};

class CameraParseBad : public ::testing::TestWithParam<BadSpec> {};

TEST_P(CameraParseBad, NamesTheBadPart) {
  EXPECT_TRUE(throwsWith<std::invalid_argument>([&] { parseCamera(GetParam().spec); }, {GetParam().part}));
}

INSTANTIATE_TEST_SUITE_P(Camera, CameraParseBad,
                         ::testing::Values(BadSpec{"", "expected EX"}, BadSpec{"1,2,3", "expected EX"},
                                           BadSpec{"1,2:0,0,0", "eye: expected 3"},
                                           BadSpec{"1,2,3,4:0,0,0", "eye: expected 3"}, BadSpec{"1,2,x:0,0,0", "eye z"},
                                           BadSpec{"1,2,3:0,0,0:45:1", "expected EX"},
                                           BadSpec{"1,2,3:0,0,0:45x", "fovy"}, BadSpec{"1,2,3:0,0,0:0", "fovy"},
                                           BadSpec{"1,2,3:0,0,0:180", "fovy"}, BadSpec{"1,2,3:0,0,0:-5", "fovy"},
                                           BadSpec{"nan,0,0:0,0,0", "eye x"}, BadSpec{"inf,0,0:0,0,0", "eye x"},
                                           BadSpec{"0,0,0:0,0,1e39", "target z"},
                                           BadSpec{"1,1,1:1,1,1", "eye equals target"},
                                           BadSpec{" 1,2,3:0,0,0", "eye x"}, BadSpec{"1,2,3:0,0,0 ", "target z"},
                                           BadSpec{"1,,3:0,0,0", "eye y"}));

TEST(CameraParse, SizeGoodAndBad) {
  int w = 0, h = 0;
  parseSize("1280x720", w, h);
  EXPECT_EQ(w, 1280);
  EXPECT_EQ(h, 720);
  parseSize("1x8192", w, h);  // the rasterizer's limit (host/scene/limits.h)
  EXPECT_EQ(h, 8192);
  for (const char* bad : {"", "1280", "1280x", "x720", "0x720", "8193x1", "1x16384", "12.5x3", "-1x3", "3x3x3",
                          "1280X720", "1280x720 "}) {
    EXPECT_THROW(parseSize(bad, w, h), std::invalid_argument) << bad;
  }
  EXPECT_TRUE(throwsWith<std::invalid_argument>([&] { parseSize("640x0", w, h); }, {"height", "1..8192"}));
}

TEST(CameraView, MapsTargetOntoNegativeZ) {
  Camera c;
  c.eye = {3, 4, 5};
  c.target = {1, 0, -2};
  const glm::vec4 t = c.view() * glm::vec4(c.target, 1);
  EXPECT_NEAR(t.x, 0, kMatrixTolerance);
  EXPECT_NEAR(t.y, 0, kMatrixTolerance);
  EXPECT_NEAR(t.z, -glm::length(c.target - c.eye), kMatrixTolerance);
}

TEST(CameraView, StraightDownAndUpStayFinite) {
  for (const glm::vec3 eye : {glm::vec3(0, 10, 0), glm::vec3(0, -10, 0), glm::vec3(1e-9f, 10, 0)}) {
    Camera c;
    c.eye = eye;
    c.target = {0, 0, 0};
    const glm::mat4 v = c.view();
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) ASSERT_TRUE(std::isfinite(v[i][j])) << eye.y;
    EXPECT_NEAR(std::abs(glm::determinant(v)), 1.0f, kMatrixTolerance);
    const glm::vec4 t = v * glm::vec4(0, 0, 0, 1);
    EXPECT_NEAR(t.z, -glm::length(eye), kMatrixTolerance);
  }
}

TEST(CameraView, ChooseUpKeepsGoodUpAndReplacesParallelOne) {
  EXPECT_EQ(chooseUp({1, 0, 0}), glm::vec3(0, 1, 0));
  EXPECT_EQ(chooseUp({0, -1, 0}), glm::vec3(0, 0, 1));
  EXPECT_EQ(chooseUp({0, 0, 1}, {0, 0, 2}), glm::vec3(1, 0, 0));
}

TEST(CameraProjection, FovAndAspect) {
  Camera c;
  c.width = 200, c.height = 100, c.fovYDeg = 90;
  const glm::mat4 p = c.projection(0.5f, 100.0f);
  EXPECT_NEAR(p[1][1], 1.0f, kMatrixTolerance);  // cot(45 degrees)
  EXPECT_NEAR(p[0][0], 0.5f, kMatrixTolerance);  // divided by the aspect 2
  const glm::vec4 nearPoint = p * glm::vec4(0, 0, -0.5f, 1);
  EXPECT_NEAR(nearPoint.z / nearPoint.w, -1.0f, kMatrixTolerance);
  EXPECT_THROW(c.projection(0.0f, 1.0f), std::invalid_argument);
  EXPECT_THROW(c.projection(2.0f, 1.0f), std::invalid_argument);
}

TEST(CameraDescribe, RoundTrips) {
  const Camera c = parseCamera("0.1,-2.5,3e-3:4,5,6:33.3");
  const Camera d = parseCamera(c.describe());
  EXPECT_EQ(d.eye, c.eye);
  EXPECT_EQ(d.target, c.target);
  EXPECT_EQ(d.fovYDeg, c.fovYDeg);
}

}  // namespace scene_camera_test
}  // namespace penumbra
