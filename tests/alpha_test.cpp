// The shared alpha sampler (kernels/shared/alpha.h, compiled here as C++: the same source the fine stage and the
// Embree filters run) against the double-precision reference (tools/selftest/reference/alpha_ref.h): every wrap mode
// pair, NEAREST and LINEAR, KHR_texture_transform, edge texels, texture-less materials, NaN, infinite and huge
// coordinates.
#include "kernels/shared/alpha.h"

#include <gtest/gtest.h>

#include <cmath>
#include <glm/gtc/constants.hpp>
#include <limits>
#include <random>
#include <utility>
#include <vector>

#include "host/scene/material.h"
#include "tools/selftest/reference/alpha_ref.h"

namespace penumbra {
namespace alpha_test {

// LINEAR: float coordinates carry a relative error of ~1e-7 of |uv| * size texels (|uv| <= 6 here, size <= 7), and
// the alpha moves by at most 1 (in 0..1 units) per texel: 1e-4 leaves a wide margin.
constexpr double kLinearTolerance = 1e-4;
// NEAREST reads the same texel away from texel edges (points within this many texels of an edge are not compared);
// the result differs only by the float product factor * texel / 255.
constexpr double kNearestEdgeTexels = 1e-3;
constexpr double kNearestTolerance = 1e-6;

// A 7x5 texture (odd sizes: no power-of-two shortcut) of random alphas at offset 3 of the atlas.
struct Fixture {
  std::vector<AlphaTexture> textures{{"test", 7, 5, 3}};
  std::vector<uint8_t> texels;
  Fixture() {
    std::mt19937 rng(7);
    texels.resize(3 + 7 * 5);
    for (uint8_t& t : texels) t = static_cast<uint8_t>(rng() & 0xff);
  }
  Material material(int wrapS, int wrapT, int filter, UvTransform transform = {}) const {
    Material m;
    m.alphaMode = AlphaMode::kMask;
    m.alphaCutoff = 0.5f;
    m.baseAlpha = 0.8f;
    m.alphaTexture = 0;
    m.wrapS = wrapS, m.wrapT = wrapT, m.filter = filter;
    m.uvTransform = transform;
    return m;
  }
  float ours(const Material& m, float u, float v) const {
    const AlphaMaterial a = alphaMaterial(m, textures);
    return alphaCoverage(&a, texels.data(), u, v);
  }
  double theirs(const Material& m, double u, double v) const { return ref::alphaCoverage(m, textures, texels, u, v); }
};

// Distance in texels from (u, v)'s transformed texel coordinate to the nearest texel edge (for NEAREST).
double edgeDistance(const Material& m, double u, double v, int w, int h) {
  const double c = std::cos(double{m.uvTransform.rotation}), s = std::sin(double{m.uvTransform.rotation});
  const double su = m.uvTransform.scale.x * u, sv = m.uvTransform.scale.y * v;
  const double x = (c * su + s * sv + m.uvTransform.offset.x) * w, y = (-s * su + c * sv + m.uvTransform.offset.y) * h;
  return std::min(std::abs(x - std::round(x)), std::abs(y - std::round(y)));
}

struct SamplerCase {
  int wrapS, wrapT, filter;
  bool transformed;
};

class AlphaSampler : public ::testing::TestWithParam<SamplerCase> {};

TEST_P(AlphaSampler, MatchesTheDoubleReference) {
  const SamplerCase& c = GetParam();
  const Fixture f;
  const UvTransform transform = c.transformed ? UvTransform{{0.25f, -0.4f}, 0.7f, {1.5f, -0.75f}} : UvTransform{};
  const Material m = f.material(c.wrapS, c.wrapT, c.filter, transform);
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> coordinate(-2.5f, 3.5f);
  int compared = 0;
  for (int i = 0; i < 4000; ++i) {
    const float u = coordinate(rng), v = coordinate(rng);
    const double expected = f.theirs(m, u, v), got = f.ours(m, u, v);
    if (c.filter == ALPHA_FILTER_NEAREST) {
      if (edgeDistance(m, u, v, 7, 5) < kNearestEdgeTexels) continue;
      ASSERT_NEAR(got, expected, kNearestTolerance) << "u " << u << " v " << v;
    } else {
      ASSERT_NEAR(got, expected, kLinearTolerance) << "u " << u << " v " << v;
    }
    ++compared;
  }
  EXPECT_GT(compared, 3900);
}

std::vector<SamplerCase> samplerCases() {
  std::vector<SamplerCase> cases;
  for (int s : {ALPHA_WRAP_REPEAT, ALPHA_WRAP_CLAMP, ALPHA_WRAP_MIRROR})
    for (int t : {ALPHA_WRAP_REPEAT, ALPHA_WRAP_CLAMP, ALPHA_WRAP_MIRROR})
      for (int filter : {ALPHA_FILTER_NEAREST, ALPHA_FILTER_LINEAR})
        for (bool transformed : {false, true}) cases.push_back({s, t, filter, transformed});
  return cases;
}

std::string samplerName(const ::testing::TestParamInfo<SamplerCase>& info) {
  static const char* kWraps[] = {"Repeat", "Clamp", "Mirror"};
  const SamplerCase& c = info.param;
  return std::string(kWraps[c.wrapS]) + kWraps[c.wrapT] + (c.filter == ALPHA_FILTER_NEAREST ? "Nearest" : "Linear") +
         (c.transformed ? "Transformed" : "");
}

INSTANTIATE_TEST_SUITE_P(WrapsFiltersTransforms, AlphaSampler, ::testing::ValuesIn(samplerCases()), samplerName);

float texel(const Fixture& f, int x, int y) { return 0.8f * f.texels[3 + y * 7 + x] / 255.0f; }

TEST(AlphaSamplerEdges, TexelCentresAndEdges) {
  const Fixture f;
  const Material nearest = f.material(ALPHA_WRAP_CLAMP, ALPHA_WRAP_CLAMP, ALPHA_FILTER_NEAREST);
  const Material linear = f.material(ALPHA_WRAP_CLAMP, ALPHA_WRAP_CLAMP, ALPHA_FILTER_LINEAR);
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 7; ++x) {  // texel centres: both filters read the texel itself
      const float u = (x + 0.5f) / 7.0f, v = (y + 0.5f) / 5.0f;
      EXPECT_FLOAT_EQ(f.ours(nearest, u, v), texel(f, x, y));
      EXPECT_NEAR(f.ours(linear, u, v), texel(f, x, y), 1e-5);
    }
  // CLAMP_TO_EDGE far outside: the edge texels; exactly on the corner too.
  EXPECT_FLOAT_EQ(f.ours(nearest, -5.0f, 0.1f), texel(f, 0, 0));
  EXPECT_FLOAT_EQ(f.ours(nearest, 9.0f, 0.99f), texel(f, 6, 4));
  EXPECT_NEAR(f.ours(linear, 0.0f, 0.0f), texel(f, 0, 0), 1e-6);
  EXPECT_NEAR(f.ours(linear, 1.0f, 1.0f), texel(f, 6, 4), 1e-6);
  // REPEAT at u = 0 between texel centres: half the last column, half the first.
  const Material repeat = f.material(ALPHA_WRAP_REPEAT, ALPHA_WRAP_CLAMP, ALPHA_FILTER_LINEAR);
  EXPECT_NEAR(f.ours(repeat, 0.0f, 0.5f / 5), 0.5f * (texel(f, 6, 0) + texel(f, 0, 0)), 1e-5);
  // MIRRORED_REPEAT just past 1 reads the last column again, just below 0 the first.
  const Material mirror = f.material(ALPHA_WRAP_MIRROR, ALPHA_WRAP_MIRROR, ALPHA_FILTER_NEAREST);
  EXPECT_FLOAT_EQ(f.ours(mirror, 1.01f, 0.1f), texel(f, 6, 0));
  EXPECT_FLOAT_EQ(f.ours(mirror, -0.01f, 0.1f), texel(f, 0, 0));
  EXPECT_FLOAT_EQ(f.ours(mirror, 1.99f, 0.1f), texel(f, 0, 0));
}

TEST(AlphaSamplerEdges, NonFiniteAndHugeCoordinatesAreDefined) {
  const Fixture f;
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  for (int wrap : {ALPHA_WRAP_REPEAT, ALPHA_WRAP_CLAMP, ALPHA_WRAP_MIRROR})
    for (int filter : {ALPHA_FILTER_NEAREST, ALPHA_FILTER_LINEAR}) {
      const Material m = f.material(wrap, wrap, filter);
      // A non-finite transformed coordinate is sampled as 0. The transform multiplies both inputs into both outputs
      // (0 x inf and 0 x NaN are NaN), so one non-finite input makes the point (0, 0), the texture's top-left corner,
      // as the reference has it too.
      for (const auto& [u, v] : {std::pair{nan, 0.3f}, std::pair{0.3f, inf}, std::pair{-inf, nan}}) {
        EXPECT_EQ(f.ours(m, u, v), f.ours(m, 0.0f, 0.0f)) << u << " " << v;
        EXPECT_NEAR(f.ours(m, u, v), f.theirs(m, u, v), kLinearTolerance) << u << " " << v;
      }
      for (float huge : {1e30f, -3e12f, 16777217.0f}) {
        const float a = f.ours(m, huge, -huge);
        EXPECT_TRUE(a >= 0.0f && a <= 0.8f) << huge << " gives " << a;
      }
    }
}

TEST(AlphaSamplerEdges, FactorCutoffAndTexturelessMaterials) {
  const Fixture f;
  Material m = f.material(ALPHA_WRAP_REPEAT, ALPHA_WRAP_REPEAT, ALPHA_FILTER_NEAREST);
  m.alphaTexture = -1;  // MASK on the factor alone
  const AlphaMaterial a = alphaMaterial(m, f.textures);
  EXPECT_EQ(a.width, 0);
  EXPECT_EQ(alphaCoverage(&a, f.texels.data(), std::nanf(""), 0.0f), 0.8f);
  EXPECT_TRUE(alphaPasses(&a, f.texels.data(), 0.0f, 0.0f));  // 0.8 >= 0.5
  m.baseAlpha = 0.3f;
  const AlphaMaterial low = alphaMaterial(m, f.textures);
  EXPECT_FALSE(alphaPasses(&low, f.texels.data(), 0.0f, 0.0f));
  // Exactly at the cutoff a fragment is drawn (glTF: opaque when alpha >= alphaCutoff).
  m.baseAlpha = 0.5f;
  const AlphaMaterial equal = alphaMaterial(m, f.textures);
  EXPECT_TRUE(alphaPasses(&equal, f.texels.data(), 0.0f, 0.0f));
  // A material that cannot discard gets cutoff 0: every fragment is drawn.
  Material opaque = m;
  opaque.alphaMode = AlphaMode::kOpaque;
  EXPECT_EQ(alphaMaterial(opaque, f.textures).cutoff, 0.0f);
}

// The extension's own example: offset (0, 1), rotation pi/2, scale 0.5 "utilizes only the lower left quadrant of the
// source image, rotated clockwise 90 degrees": the unit square's corners land on that quadrant's.
TEST(AlphaSamplerEdges, TextureTransformFollowsTheExtensionsExample) {
  float t[6];
  uvTransformMatrix({{0.0f, 1.0f}, glm::half_pi<float>(), {0.5f, 0.5f}}, t);
  const auto apply = [&](glm::vec2 p) { return glm::vec2(t[0] * p.x + t[1] * p.y + t[2], t[3] * p.x + t[4] * p.y + t[5]); };
  const float eps = 1e-6f;
  EXPECT_NEAR(glm::distance(apply({0, 0}), glm::vec2(0.0f, 1.0f)), 0.0f, eps);
  EXPECT_NEAR(glm::distance(apply({1, 0}), glm::vec2(0.0f, 0.5f)), 0.0f, eps);
  EXPECT_NEAR(glm::distance(apply({0, 1}), glm::vec2(0.5f, 1.0f)), 0.0f, eps);
  EXPECT_NEAR(glm::distance(apply({1, 1}), glm::vec2(0.5f, 0.5f)), 0.0f, eps);
  // And its second example, offset (0, 1) with scale (1, -1), flips v.
  uvTransformMatrix({{0.0f, 1.0f}, 0.0f, {1.0f, -1.0f}}, t);
  EXPECT_NEAR(glm::distance(apply({0.25f, 0.2f}), glm::vec2(0.25f, 0.8f)), 0.0f, eps);
}

}  // namespace alpha_test
}  // namespace penumbra
