// Parallel-split shadow maps (pssm, psvsm): split distances of every scheme against their closed forms (Luksch
// eq. 8, 9, 11, 15), the hard edge of the analytic square occluder, planes that stay lit, no NaN, the automatic
// scheme's one texel per pixel on a long ground plane (resolution error AOV), and no seams at split planes
// against the Embree reference (tools/reference/) on a long field of poles.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <ostream>
#include <sstream>

#include "host/pipeline/renderer.h"
#include "host/scene/load.h"
#include "host/scene/procedural.h"
#include "host/techniques/technique.h"
#include "host/views/splits.h"
#include "tests/support/cl_test.h"
#include "tests/support/render.h"
#include "tools/reference/reference.h"
#include "tools/selftest/reference/analytic_scenes.h"

namespace penumbra {
namespace pssm_test {
using test::renderWith;
using test::ClTest;

constexpr float kDistanceTolerance = 1e-5f;  // relative: float pow/mix of values up to 1e3

void expectDistances(const std::vector<float>& got, const std::vector<double>& want) {
  ASSERT_EQ(got.size(), want.size());
  for (size_t i = 0; i < want.size(); ++i) EXPECT_NEAR(got[i], want[i], kDistanceTolerance * want[i]) << "C_" << i;
}

TEST(PssmSplits, UniformLogarithmicAndPracticalMatchTheirClosedForms) {
  // n = 1, f = 100, m = 4: uniform C_i = 1 + 99 i / 4, logarithmic C_i = 100^(i / 4).
  const std::vector<double> uniform = {1, 25.75, 50.5, 75.25, 100}, logarithmic = {1, std::sqrt(10.0), 10,
                                                                                    std::sqrt(1000.0), 100};
  expectDistances(splitDistances(SplitScheme::Uniform, 4, 1, 100, 0.3f), uniform);
  expectDistances(splitDistances(SplitScheme::Logarithmic, 4, 1, 100, 0.3f), logarithmic);
  for (float lambda : {0.0f, 0.25f, 0.75f, 1.0f}) {
    std::vector<double> practical(5);
    for (size_t i = 0; i < 5; ++i) practical[i] = lambda * logarithmic[i] + (1 - lambda) * uniform[i];
    expectDistances(splitDistances(SplitScheme::Practical, 4, 1, 100, lambda), practical);  // lambda = 1: log
  }
  expectDistances(splitDistances(SplitScheme::Logarithmic, 1, 0.5f, 8, 0), {0.5, 8});
  EXPECT_THROW(splitDistances(SplitScheme::Uniform, 0, 1, 2, 0), std::invalid_argument);
  EXPECT_THROW(splitDistances(SplitScheme::Uniform, 2, 2, 1, 0), std::invalid_argument);
  EXPECT_THROW(splitDistances(SplitScheme::Practical, 2, 1, 2, 1.5f), std::invalid_argument);
}

TEST(PssmSplits, SplitBiasMovesTheInnerPlanesAndKeepsThemOrdered) {
  std::vector<float> d = {1, 25.75f, 50.5f, 75.25f, 100};
  biasSplitDistances(d, 2.0f);  // eq. 10: C_i + delta_bias
  expectDistances(d, {1, 27.75, 52.5, 77.25, 100});
  biasSplitDistances(d, -1000.0f);  // far too much: still ordered, still inside (C_0, C_m)
  for (size_t i = 1; i < d.size(); ++i) EXPECT_GT(d[i], d[i - 1]);
  EXPECT_EQ(d.front(), 1.0f);
  EXPECT_EQ(d.back(), 100.0f);
  std::vector<float> one = {1, 100};
  biasSplitDistances(one, 5.0f);
  EXPECT_EQ(one, (std::vector<float>{1, 100}));
}

TEST(PssmSplits, AutomaticSchemeFollowsTheOptimalTilingFactor) {
  EXPECT_FLOAT_EQ(optimalTilingFactor(1280, 1.5f, 1, 2048), 0.9375f);  // eq. 15: 1280 * 1.5 / 2048
  // Factor 1/2 from 100 down to 1: 100 / 2^k until below 1, i.e. ceil(log2 100) = 7 splits.
  expectDistances(autoSplitDistances(1, 100, 0.5f, 8, 0.5f), {1, 1.5625, 3.125, 6.25, 12.5, 25, 50, 100});
  // Capped at 4: two planes by the factor, the nearest two splits share [1, 25] by eq. 11 (lambda 0.5).
  expectDistances(autoSplitDistances(1, 100, 0.5f, 4, 0.5f), {1, 0.5 * 5 + 0.5 * 13, 25, 50, 100});
  expectDistances(autoSplitDistances(1, 100, 0.5f, 1, 0.5f), {1, 100});
  expectDistances(autoSplitDistances(10, 20, 0.5f, 8, 0.5f), {10, 20});  // one split already suffices
  // Eq. 16 violated (factor >= 1): the practical scheme with the most splits allowed.
  const std::vector<float> fallback = splitDistances(SplitScheme::Practical, 3, 1, 100, 0.5f);
  EXPECT_EQ(autoSplitDistances(1, 100, 1.2f, 3, 0.5f), fallback);
}

struct Variant {
  std::string technique;
  std::map<std::string, std::string> params;
};
void PrintTo(const Variant& v, std::ostream* os) {  // readable ctest names, not raw bytes
  *os << v.technique;
  for (const auto& [key, value] : v.params) *os << " --" << key << " " << value;
}
std::string variantName(const ::testing::TestParamInfo<Variant>& info) {
  std::string name = info.param.technique;
  for (const auto& [key, value] : info.param.params) name += "_" + value;
  std::replace(name.begin(), name.end(), '.', 'p');
  return name;
}

class PssmTechniques : public ClTest, public ::testing::WithParamInterface<Variant> {
 protected:
  std::map<std::string, std::string> with(std::map<std::string, std::string> extra) const {
    for (const auto& [k, v] : GetParam().params) extra.emplace(k, v);
    return extra;
  }
};

TEST_P(PssmTechniques, HardEdgeOfASquareOccluderLandsOnTheRightPixels) {
  // Spot light at y = 4: the occluder's edge |x| = 1 at y = 2 falls on |x| = 2 on the ground (as Techniques).
  // psvsm at its default bilinear lookups (--moment-filtering trilinear widens the edge by the pixel's footprint, up
  // to 8 texels on the far ground).
  const std::map<std::string, std::string> values = with({{"map-size", "1024"}});
  const RenderResult result =
      renderWith(ctx(), test::squareOverPlane(), test::topDown(), test::pointAbove(), GetParam().technique, values);
  // pssm's margin is pcf's; psvsm's the moment techniques' (its blur of split 0 + a bilinear texel).
  const test::HardEdgeMargin margin = test::hardEdgeMargin(GetParam().technique);
  const test::HardEdgeCount count = test::checkHardEdge(result.image, margin.band, margin.tolerance);
  EXPECT_GT(count.shadowed, test::kHardEdgeMinShadowed);
  EXPECT_GT(count.lit, test::kHardEdgeMinLit);
  EXPECT_EQ(count.wrong, 0);
  EXPECT_NE(result.image.attributes().at("penumbra:pssm-distances"), "");
}

TEST_P(PssmTechniques, PlanesStayFullyLitAtAnyLightAngle) {
  const Scene plane = makeProcedural("plane");
  Camera camera = test::topDown();
  camera.eye = {0.0f, 1.0f, 6.0f};  // low: a long depth range, every split in use
  for (const char* light : {"dir:0,-1,0", "dir:1,-1,0.3", "dir:1,-0.18,0", "spot:3,2,1:0,0,0:150"}) {
    const RenderResult result = renderWith(ctx(), plane, camera, parseLight(light), GetParam().technique,
                                           with({{"map-size", "256"}, {"pssm-splits", "4"}}));
    size_t dark = 0;
    for (float v : result.image.require("visibility.Y").data) dark += v < 1.0f;
    EXPECT_EQ(dark, 0u) << light << ": acne or a seam on a plane that nothing shadows";
    const auto& split = result.image.require("split.Y").data;
    EXPECT_EQ(*std::max_element(split.begin(), split.end()), 3.0f) << light;
  }
}

TEST_P(PssmTechniques, NoNanAndVisibilityInRangeOnEveryBuiltinScene) {
  for (const ProceduralInfo& info : proceduralScenes()) {
    const Scene scene = makeProcedural(info.name);
    Camera camera = scene.cameras.empty() ? test::topDown() : scene.cameras.front();
    camera.width = 96, camera.height = 64;
    const RenderResult result =
        renderWith(ctx(), scene, camera, scene.lights.front(), GetParam().technique, with({{"map-size", "128"}}));
    ASSERT_TRUE(test::saneImage(result.image, info.name));
  }
}

INSTANTIATE_TEST_SUITE_P(All, PssmTechniques,
                         ::testing::Values(Variant{"pssm", {}}, Variant{"pssm", {{"pssm-filter", "hard"}}},
                                           Variant{"pssm", {{"pssm-blend", "0.2"}, {"pssm-snap", "on"}}},
                                           Variant{"psvsm", {}}, Variant{"psvsm", {{"pssm-blend", "0.2"}}},
                                           Variant{"psvsm", {{"moment-storage", "fp16"}}}),
                         variantName);

class PssmAuto : public ClTest {};

// A 400-unit ground seen from 2 units above it, sun straight down, 160x120 pixels and 512^2 maps per split.
RenderResult longGround(Context& ctx, const std::string& splits) {
  ProceduralParams params;
  params["size"] = 400;
  const Scene scene = makeProcedural("plane", params);
  Camera camera;
  camera.eye = {0, 2, 0}, camera.target = {0, 0, -60};
  camera.width = 160, camera.height = 120;
  return renderWith(ctx, scene, camera, parseLight("dir:0,-1,0.0001"), "pssm",
                    {{"map-size", "512"}, {"pssm-splits", splits}, {"pssm-filter", "hard"}});
}

TEST_F(PssmAuto, MeetsOneTexelPerPixelOnALongGroundWithAtMostEightSplits) {
  const RenderResult one = longGround(ctx(), "1"), automatic = longGround(ctx(), "auto");
  const auto& e1 = one.image.require("resolutionError.Y").data;
  EXPECT_GT(*std::max_element(e1.begin(), e1.end()), 2.0f) << "one map over 400 units is undersampled near the camera";
  // Every pixel at or beyond its split's near plane C_s gets a texel no wider than itself (eq. 15 with sigma measured
  // on the far split: kAutoSlack covers the filter margin and the other splits' slightly different shapes). A pixel
  // that a 2x2 quad moved to the farther split lies up to one pixel row in front of C_s (a large step at grazing
  // angles): its texel is larger by C_s / z at most.
  constexpr float kAutoSlack = 0.05f;
  const auto &e = automatic.image.require("resolutionError.Y").data, &split = automatic.image.require("split.Y").data,
             &depth = automatic.image.require("depth.Z").data;
  std::vector<float> planes;
  std::istringstream text(automatic.image.attributes().at("penumbra:pssm-distances"));
  for (float d; text >> d;) planes.push_back(d);
  const int splits = static_cast<int>(planes.size()) - 1;
  EXPECT_GE(splits, 2);
  EXPECT_LE(splits, 8);
  int covered = 0, promoted = 0;
  for (size_t i = 0; i < e.size(); ++i) {
    if (split[i] < 0) continue;
    const float near = planes[static_cast<size_t>(split[i])];
    const float allowed = kAutoSlack + std::max(0.0f, std::log2(near / depth[i]));
    ++covered, promoted += depth[i] < near;
    ASSERT_LE(e[i], allowed) << "pixel " << i << " at depth " << depth[i] << " in split " << split[i] << " ("
                             << automatic.image.attributes().at("penumbra:pssm-scheme") << ")";
  }
  EXPECT_GT(covered, 8000);
  EXPECT_LT(promoted, covered / 20);
}

// The number after `key` in `text` (e.g. "smRes 640"), or -1 when it is not there.
double numberAfter(const std::string& text, const std::string& key) {
  const size_t at = text.find(key);
  return at == std::string::npos ? -1.0 : std::stod(text.substr(at + key.size()));
}

std::vector<float> planesOf(const RenderResult& r) {
  std::vector<float> planes;
  std::istringstream text(r.image.attributes().at("penumbra:pssm-distances"));
  for (float d; text >> d;) planes.push_back(d);
  return planes;
}

// --map-size auto (the default) on builtin:staircase under its disk light: the penumbrae cap the map below what the
// pixels alone need (more texels only narrow a PCF kernel of at most 4 texels), and eq. 15 plans the splits at the
// pixels' size, not at the capped one: the same split planes as a fixed map of the pixels' size. Planned at the capped
// size, eq. 15 asked for 8 splits there (each one more raster pass), which more texels per pixel do not need.
TEST_F(PssmAuto, PenumbraCappedMapsPlanTheirSplitsAtThePixelsSize) {
  const Scene scene = loadScene("builtin:staircase");
  Camera camera = scene.cameras.front();
  camera.width = 1280, camera.height = 720;
  const Light light = scene.lights.front();
  for (const char* technique : {"pssm", "psvsm"}) {
    const RenderResult automatic = renderWith(ctx(), scene, camera, light, technique, {});
    const auto& attributes = automatic.image.attributes();
    const std::string& scheme = attributes.at("penumbra:pssm-scheme");
    const double size = numberAfter(attributes.at("penumbra:map-size"), "auto ");
    const double pixels = numberAfter(scheme, "smRes ");
    ASSERT_GT(size, 0.0) << attributes.at("penumbra:map-size");
    ASSERT_GT(pixels, 0.0) << scheme;
    EXPECT_LE(size, 2048.0) << technique << ": --map-size-max for splits";
    if (std::string(technique) == "pssm") {
      EXPECT_LT(size, pixels) << attributes.at("penumbra:map-size");
    }
    const RenderResult fixed =
        renderWith(ctx(), scene, camera, light, technique, {{"map-size", std::to_string(static_cast<int>(pixels))}});
    // The same planes within the views' margins (a margin of texels is wider in the world on a smaller map).
    const std::vector<float> got = planesOf(automatic), want = planesOf(fixed);
    EXPECT_GE(got.size(), 3u) << technique << ": " << scheme;
    ASSERT_EQ(got.size(), want.size()) << technique << ": " << scheme << " against "
                                       << fixed.image.attributes().at("penumbra:pssm-scheme");
    for (size_t i = 0; i < got.size(); ++i) EXPECT_NEAR(got[i], want[i], 0.02f * want[i]) << technique << " C_" << i;
  }
}

class PssmSeams : public ClTest {};

// Poles over a long ground under a hard sun: pixels next to a split plane must be no worse against the ray-traced
// reference than the rest (a seam is a band of wrong pixels along the plane).
TEST_F(PssmSeams, SplitPlanesLeaveNoSeamAgainstTheReference) {
  const Scene scene = makeProcedural("poles");
  Camera camera = scene.cameras.front();
  camera.width = 160, camera.height = 96;
  Light light = scene.lights.front();
  light.angularRadiusDeg = 0.0f;  // hard: the reference is exact with one ray
  const reference::ReferenceResult ref = reference::renderReference(ctx(), scene, camera, light, {});
  const auto& truth = ref.image.require("visibility.Y").data;
  for (const Variant& v : {Variant{"pssm", {{"pssm-filter", "hard"}}}, Variant{"pssm", {}}, Variant{"psvsm", {}},
                           Variant{"psvsm", {{"moment-storage", "fp16"}}}}) {
    std::map<std::string, std::string> values = v.params;
    values["map-size"] = "512", values["pssm-splits"] = "4";
    const RenderResult ours = renderWith(ctx(), scene, camera, light, v.technique, values);
    const auto &vis = ours.image.require("visibility.Y").data, &split = ours.image.require("split.Y").data;
    const int w = camera.width, h = camera.height;
    // Distance (Chebyshev, pixels) to the nearest covered pixel of another split, up to kWindow.
    constexpr int kWindow = 8;
    double nearSum = 0, farSum = 0;
    int nearCount = 0, farCount = 0, boundaries = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const int i = y * w + x;
        if (split[i] < 0) continue;
        int distance = kWindow + 1;
        for (int dy = -kWindow; dy <= kWindow; ++dy)
          for (int dx = -kWindow; dx <= kWindow; ++dx) {
            const int xx = x + dx, yy = y + dy;
            if (xx >= 0 && yy >= 0 && xx < w && yy < h && split[yy * w + xx] >= 0 && split[yy * w + xx] != split[i])
              distance = std::min(distance, std::max(std::abs(dx), std::abs(dy)));
          }
        const double e = std::abs(vis[i] - truth[i]);
        if (distance <= 1) nearSum += e, ++nearCount, ++boundaries;      // at a split plane
        else if (distance >= 3 && distance <= kWindow) farSum += e, ++farCount;  // the same region, off the plane
      }
    ASSERT_GT(boundaries, 150) << v.technique;
    const double nearMae = nearSum / nearCount, farMae = farSum / farCount;
    EXPECT_LE(nearMae, 1.5 * farMae + 0.005) << v.technique << " MAE at split planes " << nearMae
                                                     << " elsewhere " << farMae;
  }
}

}  // namespace pssm_test
}  // namespace penumbra
