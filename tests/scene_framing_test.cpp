// Default views for scenes without any: the framing camera sees every corner of the bounds and the
// framing light's cone holds them, for boxes of very different sizes and shapes.
#include <cmath>

#include <gtest/gtest.h>

#include "host/scene/framing.h"
#include "scene_test_util.h"

namespace penumbra {
namespace scene_framing_test {

class SceneFraming : public ::testing::TestWithParam<Bounds> {};

TEST_P(SceneFraming, CameraAndLightCoverTheBounds) {
  const Bounds b = GetParam();
  const Camera c = framingCamera(b, 1280, 720);
  const Light l = framingLight(b);
  EXPECT_GT(l.radius, 0.0f);
  EXPECT_LT(l.axis().y, -0.5f) << "the light shines down";
  const float r = b.radius();
  const glm::mat4 viewProjection = c.projection(0.01f * r, 100.0f * r) * c.view();
  for (int i = 0; i < 8; ++i) {
    const glm::vec3 p(i & 1 ? b.max.x : b.min.x, i & 2 ? b.max.y : b.min.y, i & 4 ? b.max.z : b.min.z);
    const glm::vec4 clip = viewProjection * glm::vec4(p, 1);
    EXPECT_LT(std::max(std::abs(clip.x), std::abs(clip.y)), clip.w) << "corner " << i;
    const float angle = glm::degrees(std::acos(glm::dot(glm::normalize(p - l.position), l.axis())));
    EXPECT_LT(angle, l.fovDeg / 2) << "corner " << i;
  }
}

Bounds box(glm::vec3 min, glm::vec3 max) {
  Bounds b;
  b.grow(min), b.grow(max);
  return b;
}

INSTANTIATE_TEST_SUITE_P(Scene, SceneFraming,
                         ::testing::Values(box({-1, 0, -1}, {1, 2, 1}),
                                           box({-3.9f, 0.18f, -2.3f}, {11.6f, 25.8f, 2.3f}),
                                           box({-0.001f, -0.001f, -0.003f}, {0.006f, 0.006f, 0.0004f}),
                                           box({-50, 0, -50}, {50, 0.1f, 50}), box({0, 0, 0}, {0.1f, 10, 0.1f})));

TEST(SceneFramingErrors, EmptyBoundsAreRefused) {
  EXPECT_THROW(framingCamera(Bounds{}), std::invalid_argument);
  EXPECT_THROW(framingLight(Bounds{}), std::invalid_argument);
}

}  // namespace scene_framing_test
}  // namespace penumbra
