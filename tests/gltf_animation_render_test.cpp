// An animated glTF node through the renderer: a small card flies over a ground square, and at two --time values
// its hard shadow (sm and pcss under a sun straight down) falls where the card is at that time, matching the Embree
// reference of the same pose.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "host/eval/metrics.h"
#include "host/scene/gltf_loader.h"
#include "tests/support/cl_test.h"
#include "tests/support/gltf_builder.h"
#include "tests/support/render.h"
#include "tests/support/temp_dir.h"
#include "tools/reference/reference.h"
#include "tools/selftest/reference/analytic_scenes.h"

namespace penumbra {
namespace gltf_animation_render_test {

// Of the covered pixels able to receive light, those off by more than 0.1 from the reference: the shadow edge's
// pixels differ by the map's texels (256^2 over the fitted receivers).
constexpr double kMaxWrong = 0.01;

class GltfAnimationRender : public test::ClTest {};

// Mean visibility of the ground pixels (P.Y < 0.01) whose P.X lies within 0.1 of x, |P.Z| < 0.1.
double groundVisibility(const Image& image, float x) {
  const auto &px = image.require("P.X").data, &py = image.require("P.Y").data, &pz = image.require("P.Z").data;
  const auto &a = image.require("A").data, &v = image.require("visibility.Y").data;
  double sum = 0.0;
  int n = 0;
  for (size_t i = 0; i < v.size(); ++i)
    if (a[i] > 0.0f && py[i] < 0.01f && std::abs(px[i] - x) < 0.1f && std::abs(pz[i]) < 0.1f) sum += v[i], ++n;
  EXPECT_GT(n, 0) << "no ground pixels near x = " << x;
  return n > 0 ? sum / n : -1.0;
}

TEST_F(GltfAnimationRender, TheShadowFollowsTheAnimatedCaster) {
  std::vector<glm::vec3> soup;
  test::addQuadY(soup, 0.0f, 3.0f);
  test::GltfBuilder b(soup);
  // The same square as a card: scaled to 0.4 x 0.4 m, 1 m above the ground, flown from x = -1 to x = +1 over 1 s.
  const int card = b.addNode({{"mesh", 0}, {"scale", {0.0667, 1, 0.0667}}, {"translation", {-1, 1, 0}}});
  const int times = b.addAccessor({0, 1}, "SCALAR"), path = b.addAccessor({-1, 1, 0, 1, 1, 0}, "VEC3");
  b.doc()["animations"] = {{{"samplers", {{{"input", times}, {"output", path}}}},
                            {"channels", {{{"sampler", 0}, {"target", {{"node", card}, {"path", "translation"}}}}}}}};
  test::TempDir dir("penumbra_gltf_animation_render_test");
  const std::string file = b.write(dir.path(), "flight");
  const Light sun = parseLight("dir:0,-1,0");
  const Camera camera = test::topDown();  // 160 x 120
  for (double t : {0.0, 1.0}) {
    LoadOptions options;
    options.time = t;
    const Scene scene = loadGltf(file, options);
    const Image truth = reference::renderReference(ctx(), scene, camera, sun, {}).image;
    const float under = t == 0.0 ? -1.0f : 1.0f;
    for (const char* technique : {"sm", "pcss"}) {
      const Image image = test::renderWith(ctx(), scene, camera, sun, technique, {{"map-size", "256"}}).image;
      EXPECT_LT(compareImages(image, truth).off, kMaxWrong) << technique << " at t = " << t;
      EXPECT_LT(groundVisibility(image, under), 0.05) << technique << ": the card's shadow at t = " << t;
      EXPECT_GT(groundVisibility(image, -under), 0.95) << technique << ": where the card was not at t = " << t;
    }
  }
}

}  // namespace gltf_animation_render_test
}  // namespace penumbra
