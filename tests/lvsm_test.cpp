// Layered variance shadow maps (Lauritzen & McCool, GI 2008) on PoCL:
// - one layer is `vsm` (same moments, biases and bound: equal visibility);
// - the stacked planes: VSM bleeds light onto the ground under the middle plane, a split between the middle
//   plane and the ground removes it (sec. 3.3), and Lloyd relaxation finds such a split from a bad start;
// - Lloyd on synthetic second-occluder samples: empty clusters teleport into the heaviest layer (sec. 5);
// - 16-bit unorm layers stay within a stated tolerance of fp32 layers; the auto layer count uses the leak
//   metric; lit planes stay lit and nothing is NaN.
// Suite names contain "Lvsm" so that the pocl-loops ctest entry runs them under both work-group methods.
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/glm.hpp>
#include <sstream>

#include "host/pipeline/renderer.h"
#include "host/views/views.h"
#include "host/scene/procedural.h"
#include "host/techniques/lvsm_layers.h"
#include "host/techniques/technique.h"
#include "tests/support/cl_test.h"
#include "tests/support/render.h"

namespace penumbra {
namespace lvsm_test {
using test::ClTest;
using test::renderWith;

// 16-bit unorm layers against fp32 layers (same splits): the moments are rounded to 1/65535 (7.6e-6 half
// step), which perturbs sigma^2 = M2 - M1^2 by ~2e-5 in warped units; where the true variance is of that
// order (outer penumbra tails) the bound moves most. Measured on the stacked planes: mean 2.3e-7, max 4.6e-4.
constexpr double kUnorm16MeanTolerance = 1e-4;
constexpr double kUnorm16MaxTolerance = 5e-3;
constexpr float kBleedingThreshold = 0.02f;  // as in techniques_moments_test.cpp

std::vector<float> splitsOf(const RenderResult& r) {
  std::vector<float> s;
  std::stringstream in(r.image.attributes().at("penumbra:lvsm-splits"));
  std::string item;
  while (std::getline(in, item, ',')) s.push_back(std::stof(item));
  return s;
}

// ---- the stacked planes ---------------------------------------------------------------------------------

class LvsmStackedPlanes : public ClTest {
 protected:
  void SetUp() override {
    ClTest::SetUp();
    scene_ = makeProcedural("stacked-planes");
    camera_ = scene_.cameras.front();
    camera_.width = 160;
    camera_.height = 120;
  }
  RenderResult render(const std::string& technique, std::map<std::string, std::string> extra = {}) {
    extra.emplace("map-size", "512");
    return renderWith(ctx(), scene_, camera_, scene_.lights.front(), technique, extra);
  }
  // Normalised light depth of world point p for the map of `r` (its "depth NEAR..FAR" light-fit record).
  float normalisedDepth(const RenderResult& r, glm::vec3 p) const {
    const std::string& fit = r.image.attributes().at("penumbra:light-fit");
    float zNear = 0, zFar = 0;
    EXPECT_EQ(std::sscanf(fit.substr(fit.rfind("depth ")).c_str(), "depth %f..%f", &zNear, &zFar), 2) << fit;
    const Light& light = scene_.lights.front();
    const float depth = glm::dot(p - light.position, glm::normalize(light.target - light.position));
    return (depth - zNear) / (zFar - zNear);
  }
  // The farthest normalised depth of the middle plane and the nearest of the ground under it.
  std::pair<float, float> midAndGround(const RenderResult& r) const {
    float mid = 0.0f, ground = 1.0f;
    for (float x : {-1.5f, 1.5f})
      for (float z : {-1.5f, 1.5f}) {
        mid = std::max(mid, normalisedDepth(r, {x, 1.0f, z}));
        ground = std::min(ground, normalisedDepth(r, {x, 0.0f, z}));
      }
    return {mid, ground};
  }
  // Ground pixels whose ray to the light's centre crosses the middle plane 0.15 inside its edge: all of them
  // should be 0. Returns (pixels, pixels above kBleedingThreshold, worst).
  std::tuple<int, int, float> bleeding(const RenderResult& result) const {
    const Image& image = result.image;
    const auto &vis = image.require("visibility.Y").data, &a = image.require("A").data;
    const auto &px = image.require("P.X").data, &py = image.require("P.Y").data, &pz = image.require("P.Z").data;
    const Light& light = scene_.lights.front();
    int pixels = 0, bleeding = 0;
    float worst = 0.0f;
    for (size_t i = 0; i < vis.size(); ++i) {
      if (a[i] == 0.0f || py[i] > 0.01f) continue;
      const glm::vec3 g(px[i], py[i], pz[i]);
      const glm::vec3 onMid = g + (light.position - g) * (1.0f / light.position.y);
      if (std::max(std::abs(onMid.x), std::abs(onMid.z)) > 1.35f) continue;
      ++pixels;
      bleeding += vis[i] > kBleedingThreshold;
      worst = std::max(worst, vis[i]);
    }
    return {pixels, bleeding, worst};
  }

  Scene scene_;
  Camera camera_;
};

TEST_F(LvsmStackedPlanes, OneLayerReproducesVsm) {
  for (const char* filtering : {"bilinear", "trilinear"}) {
    const RenderResult vsm = render("vsm", {{"moment-filtering", filtering}});
    const RenderResult lvsm = render("lvsm", {{"moment-filtering", filtering}, {"lvsm-layers", "1"}});
    const auto &a = vsm.image.require("visibility.Y").data, &b = lvsm.image.require("visibility.Y").data;
    ASSERT_EQ(a.size(), b.size());
    size_t differ = 0;
    for (size_t i = 0; i < a.size(); ++i) differ += a[i] != b[i];
    EXPECT_EQ(differ, 0u) << filtering << ": pixels where 1-layer LVSM and VSM differ";
  }
}

TEST_F(LvsmStackedPlanes, VsmBleedsAndASplitBetweenMidPlaneAndGroundRemovesIt) {
  const RenderResult vsm = render("vsm");
  const auto [pixels, vsmBleeding, vsmWorst] = bleeding(vsm);
  ASSERT_GT(pixels, 1000);
  EXPECT_GT(vsmBleeding, 50) << "VSM should bleed (worst " << vsmWorst << ")";
  const auto [mid, ground] = midAndGround(vsm);
  ASSERT_LT(mid + 0.05f, ground);
  const std::string split = fmt::format("{}", 0.5f * (mid + ground));
  const RenderResult lvsm = render("lvsm", {{"lvsm-placement", "manual"}, {"lvsm-splits", split}});
  const auto [pixels2, lvsmBleeding, lvsmWorst] = bleeding(lvsm);
  RecordProperty("vsm", fmt::format("{} of {} > {}, worst {}", vsmBleeding, pixels, kBleedingThreshold, vsmWorst));
  RecordProperty("lvsm", fmt::format("split {}: {} bleeding, worst {}", split, lvsmBleeding, lvsmWorst));
  EXPECT_EQ(pixels2, pixels);
  EXPECT_EQ(lvsmBleeding, 0) << "split at " << split << ": worst " << lvsmWorst;
  EXPECT_LT(lvsmWorst, 1e-3f);
  // The split above the ground instead (between ground and the far end) leaves the bleeding in place.
  const RenderResult behind =
      render("lvsm", {{"lvsm-placement", "manual"}, {"lvsm-splits", fmt::format("{}", 0.5f * (ground + 1.0f))}});
  EXPECT_GT(std::get<1>(bleeding(behind)), 50);
}

TEST_F(LvsmStackedPlanes, LloydConvergesBetweenMidPlaneAndGroundFromABadStart) {
  const RenderResult r = render("lvsm", {{"lvsm-splits", "0.02"}});  // 2 layers, split at the near end
  const std::vector<float> s = splitsOf(r);
  const auto [mid, ground] = midAndGround(r);
  ASSERT_EQ(s.size(), 1u);
  EXPECT_GT(s[0], mid + 0.01f) << r.image.attributes().at("penumbra:lvsm-placement");
  EXPECT_LT(s[0], ground - 0.01f);
  EXPECT_NE(r.image.attributes().at("penumbra:lvsm-placement").find("converged"), std::string::npos);
  EXPECT_EQ(std::get<1>(bleeding(r)), 0) << "Lloyd's split should remove the bleeding";
}

TEST_F(LvsmStackedPlanes, EmptyLayersTeleportToTheSecondOccluderDepths) {
  // Three layers starting with both splits behind every occluder: the second split's cluster is empty.
  const RenderResult r = render("lvsm", {{"lvsm-splits", "0.97,0.99"}});
  const std::string& how = r.image.attributes().at("penumbra:lvsm-placement");
  EXPECT_EQ(how.find("teleports=0"), std::string::npos) << how;
  const std::vector<float> s = splitsOf(r);
  const auto [mid, ground] = midAndGround(r);
  ASSERT_EQ(s.size(), 2u);
  // The top plane's edges have the middle plane (nearest at its centre) as second occluder, the middle
  // plane's edges the ground.
  const float midCentre = normalisedDepth(r, {0.0f, 1.0f, 0.0f});
  EXPECT_GT(s[0], midCentre - 0.02f) << how;
  EXPECT_LT(s[0], mid + 0.02f) << how;
  EXPECT_GT(s[1], mid + 0.03f) << how;
  EXPECT_EQ(std::get<1>(bleeding(r)), 0);
  const RenderResult off = render("lvsm", {{"lvsm-splits", "0.97,0.99"}, {"lvsm-teleport", "off"}});
  EXPECT_NE(off.image.attributes().at("penumbra:lvsm-placement").find("teleports=0"), std::string::npos);
}

TEST_F(LvsmStackedPlanes, Unorm16StaysWithinToleranceOfFloat32) {
  const RenderResult f = render("lvsm"), u = render("lvsm", {{"lvsm-storage", "unorm16"}});
  EXPECT_EQ(splitsOf(f), splitsOf(u));
  const auto &a = f.image.require("visibility.Y").data, &b = u.image.require("visibility.Y").data;
  double sum = 0.0, worst = 0.0;
  for (size_t i = 0; i < a.size(); ++i) {
    sum += std::abs(a[i] - b[i]);
    worst = std::max(worst, double(std::abs(a[i] - b[i])));
  }
  RecordProperty("unorm16", fmt::format("mean {:.3g} max {:.3g}", sum / double(a.size()), worst));
  EXPECT_LE(sum / double(a.size()), kUnorm16MeanTolerance);
  EXPECT_LE(worst, kUnorm16MaxTolerance);
}

TEST_F(LvsmStackedPlanes, AutoLayerCountAddsLayersWhileTheLeakDrops) {
  const RenderResult r = render("lvsm", {{"lvsm-layers", "0"}});
  const std::string& leak = r.image.attributes().at("penumbra:lvsm-leak");
  const size_t layers = splitsOf(r).size() + 1;
  RecordProperty("leak", leak);
  EXPECT_GE(layers, 2u) << leak;
  EXPECT_LE(layers, 8u) << leak;
  const double final = std::stod(leak), one = std::stod(leak.substr(leak.find("N=1:") + 4));
  EXPECT_LT(final, 0.5 * one) << leak;
  EXPECT_EQ(std::get<1>(bleeding(r)), 0) << leak;
}

TEST_F(LvsmStackedPlanes, DebugLayersAndNoNanInEveryConfiguration) {
  const std::vector<std::map<std::string, std::string>> configs = {
      {{"lvsm-placement", "uniform"}, {"lvsm-layers", "3"}},
      {{"lvsm-storage", "unorm16"}, {"moment-filtering", "trilinear"}, {"lvsm-layers", "8"}},
      {{"lvsm-transition", "0"}, {"blur-radius", "0"}, {"lvsm-layers", "16"}}};
  for (const auto& config : configs) {
    const RenderResult r = render("lvsm", config);
    ASSERT_TRUE(test::saneImage(r.image, "lvsm"));
    const auto &layer = r.image.require("layer.Y").data, &a = r.image.require("A").data;
    const size_t n = splitsOf(r).size() + 1;
    for (size_t i = 0; i < layer.size(); ++i) {
      if (a[i] == 0.0f) continue;
      ASSERT_GE(layer[i], -1.0f);  // -1: outside the map (lit)
      ASSERT_LT(layer[i], float(n));
    }
  }
}

// Sec. 5's schedule for sequences: one step a frame, the splits kept across frames by the Renderer's technique. From
// the bad start of the test above, the one split moves every frame and reaches the every-frame relaxation's split
// (within its tolerance) and removes the bleeding in a few frames.
TEST_F(LvsmStackedPlanes, IncrementalScheduleConvergesOverFrames) {
  const RenderResult full = render("lvsm", {{"lvsm-splits", "0.02"}});
  const float target = splitsOf(full).at(0);
  const TechniqueInfo& lvsm = findTechnique("lvsm");
  const Params params =
      techniqueParams(lvsm, {{"map-size", "512"}, {"lvsm-splits", "0.02"}, {"lvsm-lloyd-schedule", "incremental"}});
  Renderer renderer(ctx(), scene_);
  std::vector<float> trail;
  RenderResult last;
  for (int frame = 0; frame < 12; ++frame) {
    last = renderer.render(camera_, scene_.lights.front(), lvsm, params);
    trail.push_back(splitsOf(last).at(0));
  }
  EXPECT_GT(trail[0], 0.02f);  // the first frame takes one step from the start
  EXPECT_LT(std::abs(trail[0] - target), std::abs(0.02f - target));
  EXPECT_NEAR(trail.back(), target, 2e-3f) << fmt::format("{}", fmt::join(trail, " "));
  EXPECT_EQ(std::get<1>(bleeding(last)), 0);
  EXPECT_NE(last.image.attributes().at("penumbra:lvsm-placement").find("lloyd incremental frame=12"),
            std::string::npos);
}

// Two of three interior splits move per frame, round-robin: the first frame leaves the third where it started.
TEST_F(LvsmStackedPlanes, IncrementalScheduleMovesTwoSplitsAFrame) {
  const TechniqueInfo& lvsm = findTechnique("lvsm");
  const Params params = techniqueParams(lvsm, {{"map-size", "512"},
                                               {"lvsm-splits", "0.3,0.5,0.7"},
                                               {"lvsm-teleport", "off"},
                                               {"lvsm-lloyd-schedule", "incremental"}});
  Renderer renderer(ctx(), scene_);
  const std::vector<float> first = splitsOf(renderer.render(camera_, scene_.lights.front(), lvsm, params));
  ASSERT_EQ(first.size(), 3u);
  EXPECT_NE(first[0], 0.3f);  // every cluster holds samples (the full relaxation ends at ~0.29, 0.46, 0.80)
  EXPECT_NE(first[1], 0.5f);
  EXPECT_EQ(first[2], 0.7f);
  const std::vector<float> second = splitsOf(renderer.render(camera_, scene_.lights.front(), lvsm, params));
  EXPECT_NE(second[2], 0.7f);  // the third's turn, with the first's
  EXPECT_EQ(second[1], first[1]);
  EXPECT_THROW(render("lvsm", {{"lvsm-lloyd-schedule", "incremental"}, {"lvsm-layers", "0"}}), std::invalid_argument);
}

TEST_F(LvsmStackedPlanes, RejectsBadSplitParameters) {
  EXPECT_THROW(render("lvsm", {{"lvsm-splits", "0.5,0.2"}}), std::invalid_argument);
  EXPECT_THROW(render("lvsm", {{"lvsm-splits", "0.2,x"}}), std::invalid_argument);
  EXPECT_THROW(render("lvsm", {{"lvsm-splits", "1.2"}}), std::invalid_argument);
  EXPECT_THROW(render("lvsm", {{"lvsm-placement", "manual"}}), std::invalid_argument);
  EXPECT_THROW(render("lvsm", {{"lvsm-transition", "0.1"}, {"lvsm-overlap", "0.01"}}), std::invalid_argument);
}

// ---- Lloyd relaxation on synthetic samples ------------------------------------------------------------------

class LvsmLloyd : public ClTest {
 protected:
  // Two tight groups of second-occluder depths: 0.3 (weight 1 each) and 0.7 (weight 2 each), plus
  // zero-weight samples that must not count.
  LvsmSamples samples() {
    std::vector<float> x, w;
    for (int i = 0; i < 3000; ++i) {
      const float jitter = 1e-3f * float(i % 7 - 3);
      x.push_back((i % 3 == 0 ? 0.3f : 0.7f) + jitter);
      w.push_back(i % 3 == 0 ? 1.0f : 2.0f);
      x.push_back(0.05f);
      w.push_back(0.0f);
    }
    LvsmSamples s;
    s.count = x.size();
    s.x = Buffer<float>(ctx(), std::span<const float>(x));
    s.w = Buffer<float>(ctx(), std::span<const float>(w));
    return s;
  }
};

TEST_F(LvsmLloyd, EmptyClustersTeleportIntoTheHeaviestLayer) {
  const LvsmSamples s = samples();
  // Both splits behind the samples: the second split's cluster stays empty.
  const LloydResult r = lloydRelax(ctx(), s, {0.0f, 0.9f, 0.95f, 1.0f}, LloydConfig{});
  ASSERT_EQ(r.splits.size(), 4u);
  EXPECT_GE(r.teleports, 1);
  EXPECT_TRUE(r.converged);
  EXPECT_NEAR(r.splits[1], 0.3f, 2e-3f);
  EXPECT_NEAR(r.splits[2], 0.7f, 2e-3f);
  LloydConfig noTeleport;
  noTeleport.teleport = false;
  const LloydResult stuck = lloydRelax(ctx(), s, {0.0f, 0.9f, 0.95f, 1.0f}, noTeleport);
  EXPECT_EQ(stuck.teleports, 0);
  EXPECT_FLOAT_EQ(stuck.splits[2], 0.95f);  // its cluster stays empty
}

TEST_F(LvsmLloyd, StopsAtTheIterationLimitAndSplitsStayOrdered) {
  const LvsmSamples s = samples();
  LloydConfig config;
  config.maxIterations = 1;
  const LloydResult one = lloydRelax(ctx(), s, {0.0f, 0.9f, 0.95f, 0.99f, 1.0f}, config);
  EXPECT_EQ(one.iterations, 1);
  EXPECT_FALSE(one.converged);
  for (size_t i = 1; i < one.splits.size(); ++i) EXPECT_LT(one.splits[i - 1], one.splits[i]);
  const LloydResult none = lloydRelax(ctx(), s, {0.0f, 1.0f}, config);  // one layer: nothing to place
  EXPECT_EQ(none.iterations, 0);
}

TEST(LvsmLayout, OverlapsAndUniformSplits) {
  const LvsmLayout l = lvsmLayout(uniformSplits(4), true, 0.02f, 0.01f, 1e-6f, 0.05f);
  EXPECT_EQ(l.count, 4u);
  EXPECT_FLOAT_EQ(l.layer[0], 0.0f);
  EXPECT_FLOAT_EQ(l.layer[1], 0.27f);
  EXPECT_FLOAT_EQ(l.layer[2], 0.23f);
  EXPECT_FLOAT_EQ(l.layer[7], 1.0f);
  EXPECT_EQ(parseSplits("0.2,0.5"), (std::vector<float>{0.0f, 0.2f, 0.5f, 1.0f}));
  EXPECT_EQ(formatSplits({0.0f, 0.2f, 0.5f, 1.0f}), "0.2,0.5");
}

}  // namespace lvsm_test
}  // namespace penumbra
