// End-to-end tests of the moment-based techniques (vsm, evsm2/4, esm, msm, savsm) on PoCL:
// - VSM is exact for one planar occluder over a parallel planar receiver: with a box blur of 2r+1 texels it
//   equals the fraction of unoccluded texels under the same box (PCF), checked against a CPU reference;
//   SAVSM with a fixed box of the same width (every SAT precision), EVSM, ESM and MSM come within a stated
//   tolerance of the same;
// - the three stacked planes show VSM's light bleeding on the ground, the reduction amount removes it, and
//   MSM and EVSM4 bleed less than VSM;
// - the same with fp16 moment storage (vsm, evsm2/4, esm, msm) within a stated tolerance;
// - non-default configurations (trilinear lookups, SAVSM width modes and precisions, fp16 storage with mips and
//   running-sum blurs) keep planes fully lit and produce no NaN.
// Suite names contain "Techniques" so that the pocl-loops ctest entry runs them under both work-group methods.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>

#include "host/pipeline/renderer.h"
#include "host/scene/procedural.h"
#include "host/scene/procedural_mesh.h"
#include "host/techniques/technique.h"
#include "host/views/views.h"
#include "tests/support/cl_test.h"
#include "tests/support/render.h"
#include "tools/selftest/reference/box_pcf_ref.h"

namespace penumbra {
namespace techniques_moments_test {
using test::ClTest;
using test::renderWith;

// fp32 moments: M2 - M1^2 cancels to ~1e-7 absolute, and the kernel's bilinear weights come from fp32
// texel coordinates (~1e-5 texel). Measured worst: 1e-6 (vsm), 2e-6 (savsm, every precision).
constexpr double kPlanarTolerance = 1e-4;
// MSM's moment bias alpha = 3e-5 and the fp32 decoding of the quantised moments perturb the two-depth
// bound. Measured worst: 1.2e-5.
constexpr double kPlanarMsmTolerance = 1e-3;
// EVSM4 and ESM: the warps e^(c x) amplify the fp32 rounding of x by c = 40 (ESM's 80 on [0, 1]). Measured worst:
// 6.7e-5, 4.0e-5.
constexpr double kPlanarExpTolerance = 3e-4;
// EVSM2: the minimum variance, carried through the warp (slope 2c = 80 at the mean), exceeds the true warped
// variance f (1 - f) dw^2 where the occluded fraction f < (2c)^2 min-variance = 0.64%, which brightens the
// outer penumbra by up to ~f. Measured worst: 1.6e-3 (EVSM4's negative bound hides it).
constexpr double kPlanarEvsm2Tolerance = 3e-3;
// fp16 moment storage (11 significant bits: moments within 2^-12 relative, M1 near 1 within 2.4e-4; EVSM exponents
// clamped to 5.54, ESM's (log space: its error is c times the depth's rounding) to 8; MSM's moment bias raised to at
// least 1e-3). Measured worst: vsm 2.5e-4, evsm2 and
// evsm4 6.9e-4, esm 2.6e-4, msm 6.1e-4 (with the default alpha 3e-5 it would be 1.8e-2).
constexpr double kPlanarHalfTolerance = 2e-3;

// ---- one planar occluder over a parallel planar receiver -----------------------------------------------

constexpr int kPlanarMap = 128;
constexpr int kPlanarRadius = 4;  // box of 9 x 9 texels (0.7 world units): a wide band of partial coverage
constexpr float kOccluderY = 2.0f;

Scene planarScene(glm::vec2 lo, glm::vec2 hi) {
  Scene scene;
  detail::addHorizontalQuad(scene, detail::addObject(scene, "ground"), -5, 5, -5, 5, 0);
  detail::addHorizontalQuad(scene, detail::addObject(scene, "occluder"), lo.x, hi.x, lo.y, hi.y, kOccluderY);
  return scene;
}

// The light's map for `scene` as the technique fits it with --fit scene, and its texel <-> world maps.
struct MapFrame {
  glm::mat4 toClip, toWorld;
  glm::vec3 world(double u, double v) const {  // texel coordinates at the occluder's height -> world
    glm::vec4 ndc(static_cast<float>(2 * u / kPlanarMap - 1), static_cast<float>(2 * v / kPlanarMap - 1), 0, 1);
    glm::vec4 w = toWorld * ndc;
    glm::vec3 p = glm::vec3(w) / w.w;
    return p;
  }
  glm::dvec2 texel(const glm::vec3& p) const {
    const glm::vec4 c = toClip * glm::vec4(p, 1.0f);
    return {(c.x / c.w * 0.5 + 0.5) * kPlanarMap, (c.y / c.w * 0.5 + 0.5) * kPlanarMap};
  }
};

MapFrame mapFrame(const Scene& scene, const Light& light) {
  const LightView view = fitLightView(light, scene.bounds(), kPlanarMap);
  MapFrame f;
  f.toClip = view.raster.projection * view.raster.view;
  f.toWorld = glm::inverse(f.toClip);
  return f;
}

// Snaps world x and z to the nearest texel boundary of a straight-down orthographic map, so that no texel
// centre lies near the occluder's edges and the rasterizer's coverage is unambiguous.
glm::vec2 snapToTexels(const MapFrame& f, glm::vec2 p) {
  const glm::vec3 origin = f.world(0, 0), step = f.world(1, 1) - origin;
  auto snap = [](float x, float o, float s) { return o + std::round((x - o) / s) * s; };
  return {snap(p.x, origin.x, std::abs(step.x)), snap(p.y, origin.z, std::abs(step.z))};
}

// The CPU reference for `scene`: occlusion flags at the texel centres (inside the occluder's rectangle).
ref::BoxPcf boxPcfReference(const MapFrame& f, glm::vec2 lo, glm::vec2 hi, int radius) {
  std::vector<double> occluded(size_t(kPlanarMap) * kPlanarMap);
  for (int y = 0; y < kPlanarMap; ++y)
    for (int x = 0; x < kPlanarMap; ++x) {
      const glm::vec3 c = f.world(x + 0.5, y + 0.5);
      occluded[size_t(y) * kPlanarMap + x] = c.x > lo.x && c.x < hi.x && c.z > lo.y && c.z < hi.y;
    }
  return ref::BoxPcf(occluded, kPlanarMap, radius);
}

struct PlanarCase {
  std::string technique;
  std::map<std::string, std::string> params;
  double tolerance;
};

void PrintTo(const PlanarCase& c, std::ostream* os) { *os << c.technique; }

class MomentTechniquesPlanar : public ClTest, public ::testing::WithParamInterface<PlanarCase> {};

TEST_P(MomentTechniquesPlanar, EqualsBoxFilteredPcfForAPlanarOccluderOverAParallelReceiver) {
  const Light light = parseLight("dir:0,-1,0");
  const MapFrame frame = mapFrame(planarScene({-1, -1}, {1, 1}), light);  // the fit depends on the bounds only
  const glm::vec2 lo = snapToTexels(frame, {-1.3f, -1.1f}), hi = snapToTexels(frame, {0.9f, 1.2f});
  const Scene scene = planarScene(lo, hi);
  Camera camera;
  camera.eye = {0.0f, 8.0f, 4.0f};
  camera.target = {0.0f, 0.0f, 0.0f};
  camera.width = 160;
  camera.height = 120;
  std::map<std::string, std::string> params = {{"map-size", std::to_string(kPlanarMap)},
                                               {"fit", "scene"},
                                               {"bias", "0"},
                                               {"slope-bias", "0"},
                                               {"normal-offset", "0"}};
  params.insert(GetParam().params.begin(), GetParam().params.end());
  auto precision = params.find("sat-precision");
  if (precision != params.end() && precision->second == "double" && !ctx().info().fp64)
    GTEST_SKIP() << ctx().info().name << " has no fp64";
  const RenderResult result = renderWith(ctx(), scene, camera, light, GetParam().technique, params);

  const ref::BoxPcf reference = boxPcfReference(frame, lo, hi, kPlanarRadius);
  const Image& image = result.image;
  const auto &vis = image.require("visibility.Y").data, &a = image.require("A").data;
  const auto &px = image.require("P.X").data, &py = image.require("P.Y").data, &pz = image.require("P.Z").data;
  int partial = 0, checked = 0, wrong = 0;
  double worst = 0.0;
  for (size_t i = 0; i < vis.size(); ++i) {
    if (a[i] == 0.0f || py[i] > 0.5f) continue;  // background, or the occluder's top
    const double expected = reference.visibility(frame.texel({px[i], py[i], pz[i]}));
    partial += expected > 0.05 && expected < 0.95;
    ++checked;
    const double error = std::abs(vis[i] - expected);
    worst = std::max(worst, error);
    if (error > GetParam().tolerance && ++wrong <= 5)
      ADD_FAILURE() << "pixel " << i << " at (" << px[i] << ", " << pz[i] << "): " << vis[i] << " vs " << expected;
  }
  if (GetParam().technique == "savsm") {  // the debug layer reports the box actually used
    const auto& width = image.require("filterWidth.Y").data;
    for (size_t i = 0; i < vis.size(); ++i) {
      if (a[i] == 0.0f || py[i] > 0.5f) continue;
      ASSERT_EQ(width[i], 2 * kPlanarRadius + 1) << "pixel " << i;
    }
  }
  EXPECT_GT(checked, 10000);
  EXPECT_GT(partial, 300) << "the footprint must straddle the occluder's edges on many pixels";
  EXPECT_EQ(wrong, 0) << GetParam().technique << ": worst |difference| " << worst;
  RecordProperty("worst_difference", fmt::format("{:.3g}", worst));
}

const std::string kRadius = std::to_string(kPlanarRadius), kWidth = std::to_string(2 * kPlanarRadius + 1);
const std::map<std::string, std::string> kBox = {{"blur-filter", "box"}, {"blur-radius", kRadius}};
// esm at the paper's exponent: under auto this test's zero biases let the ground's own acne count as occluders at
// distance 0, which picks the largest exponent (1000), and with it c times the depths' fp32 rounding (measured 4.8e-4).
const std::map<std::string, std::string> kBoxEsm = {
    {"blur-filter", "box"}, {"blur-radius", kRadius}, {"esm-exponent", "80"}};
const std::map<std::string, std::string> kBoxHalf = {
    {"blur-filter", "box"}, {"blur-radius", kRadius}, {"moment-storage", "fp16"}};

INSTANTIATE_TEST_SUITE_P(
    Box, MomentTechniquesPlanar,
    ::testing::Values(PlanarCase{"vsm", kBox, kPlanarTolerance},
                      PlanarCase{"savsm",
                                 {{"savsm-width-from", "fixed"}, {"savsm-width", kWidth}, {"sat-precision", "float"}},
                                 kPlanarTolerance},
                      PlanarCase{"savsm",
                                 {{"savsm-width-from", "fixed"}, {"savsm-width", kWidth}, {"sat-precision", "fixed32"}},
                                 kPlanarTolerance},
                      PlanarCase{"savsm",
                                 {{"savsm-width-from", "fixed"}, {"savsm-width", kWidth}, {"sat-precision", "fixed64"}},
                                 kPlanarTolerance},
                      PlanarCase{"savsm",
                                 {{"savsm-width-from", "fixed"}, {"savsm-width", kWidth}, {"sat-precision", "double"}},
                                 kPlanarTolerance},
                      PlanarCase{"evsm2", kBox, kPlanarEvsm2Tolerance}, PlanarCase{"evsm4", kBox, kPlanarExpTolerance},
                      PlanarCase{"esm", kBoxEsm, kPlanarExpTolerance}, PlanarCase{"msm", kBox, kPlanarMsmTolerance},
                      PlanarCase{"vsm", kBoxHalf, kPlanarHalfTolerance},
                      PlanarCase{"evsm2", kBoxHalf, kPlanarHalfTolerance},
                      PlanarCase{"evsm4", kBoxHalf, kPlanarHalfTolerance},
                      PlanarCase{"esm", kBoxHalf, kPlanarHalfTolerance},
                      PlanarCase{"msm", kBoxHalf, kPlanarHalfTolerance}),
    [](const ::testing::TestParamInfo<PlanarCase>& p) {
      std::string name = p.param.technique;
      for (const char* key : {"sat-precision", "moment-storage"})
        if (auto value = p.param.params.find(key); value != p.param.params.end()) name += "_" + value->second;
      return name;
    });

// ---- three stacked planes: light bleeding -----------------------------------------------------------

// Visibility on the ground where the middle plane blocks the light's centre (more than `margin` world units
// inside its shadow): all of it should be 0.
struct Bleeding {
  int pixels = 0, bleeding = 0;  // ground pixels in the umbra; those with visibility > kBleedingThreshold
  float worst = 0.0f;
};
constexpr float kBleedingThreshold = 0.02f;

Bleeding measureBleeding(const RenderResult& result, const Light& light, float gap, float margin) {
  const Image& image = result.image;
  const auto &vis = image.require("visibility.Y").data, &a = image.require("A").data;
  const auto &px = image.require("P.X").data, &py = image.require("P.Y").data, &pz = image.require("P.Z").data;
  Bleeding b;
  for (size_t i = 0; i < vis.size(); ++i) {
    if (a[i] == 0.0f || py[i] > 0.01f) continue;
    const glm::vec3 g(px[i], py[i], pz[i]);
    const glm::vec3 onMid = g + (light.position - g) * (gap / light.position.y);  // ray to the light at y = gap
    if (std::max(std::abs(onMid.x), std::abs(onMid.z)) > 1.5f - margin) continue;
    ++b.pixels;
    b.bleeding += vis[i] > kBleedingThreshold;
    b.worst = std::max(b.worst, vis[i]);
  }
  return b;
}

class MomentTechniquesBleeding : public ClTest {};

TEST_F(MomentTechniquesBleeding, StackedPlanesBleedUnderVsmAndTheReductionRemovesIt) {
  const Scene scene = makeProcedural("stacked-planes");
  Camera camera = scene.cameras.front();
  camera.width = 160;
  camera.height = 120;
  const Light& light = scene.lights.front();
  const std::map<std::string, std::string> common = {{"map-size", "512"}};
  auto measure = [&](const std::string& technique, std::map<std::string, std::string> extra = {}) {
    extra.insert(common.begin(), common.end());
    return measureBleeding(renderWith(ctx(), scene, camera, light, technique, extra), light, 1.0f, 0.15f);
  };
  const Bleeding vsm = measure("vsm"), reduced = measure("vsm", {{"bleeding-reduction", "0.2"}});
  const Bleeding msm = measure("msm"), evsm4 = measure("evsm4");
  RecordProperty("vsm",
                 fmt::format("{} of {} > {}, worst {}", vsm.bleeding, vsm.pixels, kBleedingThreshold, vsm.worst));
  RecordProperty("msm", fmt::format("{} bleeding, worst {}", msm.bleeding, msm.worst));
  RecordProperty("evsm4", fmt::format("{} bleeding, worst {}", evsm4.bleeding, evsm4.worst));
  ASSERT_GT(vsm.pixels, 1000);
  EXPECT_GT(vsm.bleeding, 50) << "VSM should bleed light around the top plane's shadow (worst " << vsm.worst << ")";
  EXPECT_GT(vsm.worst, 0.05f);
  EXPECT_EQ(reduced.bleeding, 0) << "worst " << reduced.worst;
  EXPECT_LT(msm.worst, 0.5f * vsm.worst) << "MSM bleeds " << msm.bleeding << " pixels";
  EXPECT_LT(msm.bleeding, vsm.bleeding);
  EXPECT_LT(evsm4.worst, 0.5f * vsm.worst) << "EVSM4 bleeds " << evsm4.bleeding << " pixels";
}

// ---- other configurations: lit planes stay lit, no NaN ---------------------------------------------------

struct ConfigCase {
  std::string name, technique;
  std::map<std::string, std::string> params;
  float litTolerance = 0.0f;  // lit means visibility >= 1 - litTolerance
};

// MSM with trilinear lookups at a grazing light: near the plane's far edge the coarse mip texels mix the
// plane with the background (depth 1) behind it, and the four-moment bound of that mixture leaves up to
// 3e-4 (measured) of shadow on a lit receiver.
constexpr float kMsmTrilinearLitTolerance = 1e-3f;

void PrintTo(const ConfigCase& c, std::ostream* os) { *os << c.name; }

class MomentTechniquesConfigs : public ClTest, public ::testing::WithParamInterface<ConfigCase> {};

TEST_P(MomentTechniquesConfigs, PlanesStayLitAndNoNanOnStackedPlanes) {
  const Scene plane = makeProcedural("plane");
  Camera camera;
  camera.eye = {0.0f, 6.0f, 6.0f};
  camera.target = {0.0f, 0.0f, 0.0f};
  camera.width = 96;
  camera.height = 64;
  std::map<std::string, std::string> params = GetParam().params;
  params.emplace("map-size", "512");
  for (const char* light : {"dir:0,-1,0", "dir:1,-0.18,0", "spot:3,2,1:0,0,0:150"}) {
    const RenderResult result = renderWith(ctx(), plane, camera, parseLight(light), GetParam().technique, params);
    size_t dark = 0;
    for (float v : result.image.require("visibility.Y").data) dark += v < 1.0f - GetParam().litTolerance;
    EXPECT_EQ(dark, 0u) << GetParam().name << " under " << light;
  }
  const Scene stacked = makeProcedural("stacked-planes");
  Camera view = stacked.cameras.front();
  view.width = 96;
  view.height = 64;
  const RenderResult result = renderWith(ctx(), stacked, view, stacked.lights.front(), GetParam().technique, params);
  ASSERT_TRUE(test::saneImage(result.image, GetParam().name));
  EXPECT_NE(result.image.find("moments.M1"), nullptr) << "debug layers";
}

INSTANTIATE_TEST_SUITE_P(
    All, MomentTechniquesConfigs,
    ::testing::Values(
        ConfigCase{"vsm_trilinear", "vsm", {{"moment-filtering", "trilinear"}}},
        ConfigCase{"msm_trilinear_box",
                   "msm",
                   {{"moment-filtering", "trilinear"}, {"blur-filter", "box"}, {"blur-radius", "2"}},
                   kMsmTrilinearLitTolerance},
        ConfigCase{"evsm4_unblurred", "evsm4", {{"blur-radius", "0"}, {"bleeding-reduction", "0.3"}}},
        ConfigCase{"esm_trilinear", "esm", {{"moment-filtering", "trilinear"}}},
        ConfigCase{"savsm_footprint", "savsm", {{"savsm-width-from", "footprint"}}},
        ConfigCase{"savsm_float", "savsm", {{"sat-precision", "float"}}},
        ConfigCase{"savsm_fixed64", "savsm", {{"sat-precision", "fixed64"}}},
        ConfigCase{"vsm_fp16_trilinear", "vsm", {{"moment-storage", "fp16"}, {"moment-filtering", "trilinear"}}},
        ConfigCase{"evsm4_fp16_running_sums",
                   "evsm4",
                   {{"moment-storage", "fp16"}, {"blur-radius", "40"}, {"moment-filtering", "trilinear"}}},
        ConfigCase{"msm_fp16_trilinear",
                   "msm",
                   {{"moment-storage", "fp16"}, {"moment-filtering", "trilinear"}},
                   kMsmTrilinearLitTolerance},
        ConfigCase{"esm_fp16_unblurred", "esm", {{"moment-storage", "fp16"}, {"blur-radius", "0"}}}),
    [](const ::testing::TestParamInfo<ConfigCase>& p) { return p.param.name; });

}  // namespace techniques_moments_test
}  // namespace penumbra
