// The light fit (host/views/light_fit.h, views.h, kernels/fit.cl): the device reductions against plain
// C++ over the same data, adversarial inputs (NaN, background only, empty), and the fitted view keeping
// every visible receiver inside the map with the requested margin while using fewer world units per texel.
#include "host/views/light_fit.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "host/scene/procedural.h"
#include "host/views/raster_scene.h"
#include "host/views/views.h"
#include "raster/rasterizer.h"
#include "tests/support/cl_test.h"
#include "tools/selftest/reference/analytic_scenes.h"

namespace penumbra {
namespace light_fit_test {
using test::ClTest;

class LightFit : public ClTest {};

glm::vec3 project(const LightView& lv, glm::vec3 world) {  // lv_project on the host
  const glm::vec4 clip = lv.raster.projection * lv.raster.view * glm::vec4(world, 1.0f);
  const glm::vec2 ndc = glm::vec2(clip) / clip.w;
  const float depth = -(lv.raster.view * glm::vec4(world, 1.0f)).z;
  return {(ndc.x * 0.5f + 0.5f) * lv.gpu.width, (ndc.y * 0.5f + 0.5f) * lv.gpu.height, depth};
}

TEST_F(LightFit, DepthRangeIgnoresBackgroundAndNan) {
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<float> depth(1000 * 37 + 5, inf);  // not a multiple of the work-group
  depth[17] = 3.5f, depth[30000] = -2.0f, depth[36999] = 9.25f, depth[123] = nan, depth[5] = -inf;
  Buffer<float> buffer(ctx(), std::span<const float>(depth));
  const DepthRange range = reduceDepthRange(ctx(), buffer, depth.size());
  EXPECT_EQ(range.min, -2.0f);
  EXPECT_EQ(range.max, 9.25f);

  std::vector<float> empty(1, inf);
  Buffer<float> one(ctx(), std::span<const float>(empty));
  const DepthRange none = reduceDepthRange(ctx(), one, 1);
  EXPECT_GT(none.min, none.max) << "no finite depth: an empty range";

  // A map-sized input: every work-item's slice long (the CPU layout's 8-wide loop and its tail), holes anywhere, the
  // extremes at the first, the last and an odd index.
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> unit(1.0f, 2.0f);
  std::vector<float> map(1531 * 1031);
  for (float& z : map) z = unit(rng);
  for (size_t i = 0; i < map.size(); i += 97) map[i] = (i / 97) % 3 == 0 ? nan : inf;
  map[0] = 0.5f, map[map.size() - 1] = 7.0f, map[777777] = nan, map[777779] = -inf;
  Buffer<float> big(ctx(), std::span<const float>(map));
  const DepthRange range2 = reduceDepthRange(ctx(), big, map.size());
  EXPECT_EQ(range2.min, 0.5f);
  EXPECT_EQ(range2.max, 7.0f);
  map[0] = 1.25f, map[map.size() - 1] = 1.5f, map[1234567] = 0.25f, map[1234569] = 9.0f;
  big.upload(ctx(), std::span<const float>(map));
  const DepthRange range3 = reduceDepthRange(ctx(), big, map.size());
  EXPECT_EQ(range3.min, 0.25f);
  EXPECT_EQ(range3.max, 9.0f);
}

TEST_F(LightFit, ReceiverBoxMatchesTheGBufferOnTheHost) {
  const Scene scene = test::squareOverPlane();
  Camera camera = test::topDown();
  camera.width = 97, camera.height = 61;  // odd sizes
  Rasterizer raster(ctx());
  uploadScene(raster, scene);
  GBuffer g;
  raster.drawGBuffer(cameraView(camera, scene.bounds()), g);
  for (const char* spec : {"spot:0,4,0:0,0,0:120", "dir:1,-1,0.3"}) {
    const Light light = parseLight(spec);
    const bool perspective = light.type == LightType::Spot;
    const glm::mat4 eye = lightEyeMatrix(light, scene.bounds());
    const ReceiverBounds box = reduceReceivers(ctx(), g, eye, perspective);
    glm::vec3 lo(INFINITY), hi(-INFINITY);
    for (const cl_float4& p : g.position.download(ctx())) {
      if (p.s[3] == 0.0f) continue;
      const glm::vec4 e = eye * glm::vec4(p.s[0], p.s[1], p.s[2], 1.0f);
      const float d = -e.z;
      const glm::vec3 v(perspective ? glm::vec2(e) / d : glm::vec2(e), d);
      lo = glm::min(lo, v), hi = glm::max(hi, v);
    }
    ASSERT_FALSE(box.empty) << spec;
    EXPECT_NEAR(box.lo.x, lo.x, 1e-5f) << spec;
    EXPECT_NEAR(box.lo.y, lo.y, 1e-5f) << spec;
    EXPECT_NEAR(box.hi.x, hi.x, 1e-5f) << spec;
    EXPECT_NEAR(box.hi.y, hi.y, 1e-5f) << spec;
    EXPECT_NEAR(box.depthMin, lo.z, 1e-4f) << spec;
    EXPECT_NEAR(box.depthMax, hi.z, 1e-4f) << spec;
  }
}

TEST_F(LightFit, CameraSeeingNothingGivesAnEmptyBoxAndTheWholeSceneFit) {
  const Scene scene = test::squareOverPlane();
  Camera away = test::topDown();
  away.target = {0.0f, 20.0f, 5.0f};  // looks up, away from everything
  Rasterizer raster(ctx());
  uploadScene(raster, scene);
  GBuffer g;
  raster.drawGBuffer(cameraView(away, scene.bounds()), g);
  const Light light = parseLight("dir:0,-1,0");
  const ReceiverBounds box = reduceReceivers(ctx(), g, lightEyeMatrix(light, scene.bounds()), false);
  EXPECT_TRUE(box.empty);
  const LightView fitted = fitLightView(light, scene.bounds(), 256, &box, 4.0f);
  const LightView whole = fitLightView(light, scene.bounds(), 256);
  EXPECT_EQ(fitted.gpu.texelScale, whole.gpu.texelScale);
}

TEST_F(LightFit, EveryReceiverLandsInsideTheMarginAndTexelsShrink) {
  const Scene scene = test::squareOverPlane();
  Camera close = test::topDown();
  close.eye = {1.0f, 2.5f, 2.5f};  // sees a corner of the ground and part of the occluder
  close.target = {1.5f, 0.0f, 1.0f};
  Rasterizer raster(ctx());
  uploadScene(raster, scene);
  GBuffer g;
  raster.drawGBuffer(cameraView(close, scene.bounds()), g);
  const std::vector<cl_float4> positions = g.position.download(ctx());
  constexpr int kSize = 512;
  constexpr float kMargin = 8.0f;
  for (const char* spec : {"spot:0,4,0:0,0,0:120", "dir:1,-1,0.3"}) {
    const Light light = parseLight(spec);
    const ReceiverBounds box = reduceReceivers(ctx(), g, lightEyeMatrix(light, scene.bounds()),
                                               light.type == LightType::Spot);
    ASSERT_FALSE(box.empty) << spec;
    const LightView fitted = fitLightView(light, scene.bounds(), kSize, &box, kMargin);
    const LightView whole = fitLightView(light, scene.bounds(), kSize);
    EXPECT_LT(fitted.gpu.texelScale, 0.6f * whole.gpu.texelScale) << spec << ": the crop should zoom in";
    int receivers = 0;
    for (const cl_float4& p : positions) {
      if (p.s[3] == 0.0f) continue;
      ++receivers;
      const glm::vec3 t = project(fitted, {p.s[0], p.s[1], p.s[2]});
      ASSERT_GE(t.x, kMargin - 0.01f) << spec;
      ASSERT_GE(t.y, kMargin - 0.01f) << spec;
      ASSERT_LE(t.x, kSize - kMargin + 0.01f) << spec;
      ASSERT_LE(t.y, kSize - kMargin + 0.01f) << spec;
      ASSERT_LE(t.z, fitted.gpu.zFar) << spec << ": a visible receiver beyond the far plane";
      ASSERT_GE(t.z, fitted.gpu.zNear) << spec;
    }
    EXPECT_GT(receivers, 1000);
    // The occluder (y = 2) sits between the light and the receivers: the near plane must keep it.
    EXPECT_LE(fitted.gpu.zNear, project(fitted, {1.0f, 2.0f, 1.0f}).z) << spec;
  }
}

}  // namespace light_fit_test
}  // namespace penumbra
