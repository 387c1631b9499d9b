// The sm/pcf/pcss options beyond the basics: receiver-plane depth bias (acne-free without slope bias),
// the adaptive PCF kernel (grows with the pixel's footprint in the map), rotated Poisson taps (same shadow
// edge as the grid), the receiver fit (same hard edge as the whole-scene fit, finer texels), and pcss's reach scaled
// with the map (--pcss-max-radius auto), and pcss's tap counts from each pixel's region (--pcss-*-taps auto).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "host/scene/procedural.h"
#include "tests/support/cl_test.h"
#include "tests/support/render.h"
#include "tools/reference/tracer.h"
#include "tools/selftest/reference/analytic_scenes.h"

namespace penumbra {
namespace techniques_pcf_test {
using test::ClTest;

class PcfTechniques : public ClTest {
 protected:
  static RenderResult render(const Scene& scene, const Camera& camera, const Light& light, const std::string& name,
                             const test::Values& values) {
    return test::renderWith(ctx(), scene, camera, light, name, values);
  }

  // Fraction of covered pixels with visibility below 1.
  static double darkFraction(const RenderResult& result) {
    const auto &vis = result.image.require("visibility.Y").data, &a = result.image.require("A").data;
    size_t covered = 0, dark = 0;
    for (size_t i = 0; i < vis.size(); ++i)
      if (a[i] > 0.0f) ++covered, dark += vis[i] < 1.0f;
    return covered ? static_cast<double>(dark) / static_cast<double>(covered) : 0.0;
  }
};

TEST_F(PcfTechniques, ReceiverPlaneBiasKeepsAGrazingPlaneLitWithoutSlopeBias) {
  const Scene plane = test::withSliverBelow(makeProcedural("plane"));  // a plane that may shadow
  Camera camera = test::topDown();
  camera.eye = {0.0f, 6.0f, 6.0f};
  const Light grazing = parseLight("dir:1,-0.25,0.2");  // ~75 degrees from the normal
  for (const char* name : {"sm", "pcf", "pcss"}) {
    test::Values values = {
        {"map-size", "512"}, {"bias", "0.05"}, {"slope-bias", "0"}, {"normal-offset", "0"}, {"fit", "scene"}};
    values["receiver-plane"] = "off";
    const double without = darkFraction(render(plane, camera, grazing, name, values));
    values["receiver-plane"] = "on";
    const double with = darkFraction(render(plane, camera, grazing, name, values));
    EXPECT_GT(without, 0.05) << name << ": without any slope bias a grazing plane should show acne";
    EXPECT_LT(with, 0.002) << name << ": the receiver plane should remove it (was " << without << ")";
  }
}

TEST_F(PcfTechniques, AdaptiveKernelFollowsThePixelFootprint) {
  const Scene plane = makeProcedural("plane");
  Camera grazing = test::topDown();
  grazing.eye = {0.0f, 0.6f, 6.0f};  // low over the plane: footprints grow towards the horizon
  grazing.target = {0.0f, 0.0f, -2.0f};
  const Light light = parseLight("dir:0,-1,0");
  test::Values values = {{"map-size", "1024"}, {"pcf-radius", "1"}, {"fit", "scene"}};
  values["pcf-adaptive"] = "off";
  {
    const RenderResult fixed = render(plane, grazing, light, "pcf", values);
    const auto &r = fixed.image.require("filter.Z").data, &covered = fixed.image.require("A").data;
    for (size_t i = 0; i < r.size(); ++i)
      ASSERT_EQ(r[i], covered[i] > 0.0f ? 1.0f : 0.0f)
          << "fixed kernel: half-width 1 on every covered pixel (" << i << ")";
  }
  values["pcf-adaptive"] = "on";
  values["pcf-max-radius"] = "12";
  const RenderResult result = render(plane, grazing, light, "pcf", values);
  const auto& width = result.image.require("filter.Z").data;
  const auto& a = result.image.require("A").data;
  const int w = grazing.width;
  float nearRow = 0.0f, farRow = 0.0f;  // image rows are top-down: the horizon is near the top
  int nearCount = 0, farCount = 0;
  for (size_t i = 0; i < width.size(); ++i) {
    if (a[i] == 0.0f) continue;
    ASSERT_GE(width[i], 1.0f);
    ASSERT_LE(width[i], 12.0f);
    const int y = static_cast<int>(i) / w;
    if (y > grazing.height * 9 / 10) nearRow += width[i], ++nearCount;
    if (y < grazing.height / 2) farRow += width[i], ++farCount;
  }
  ASSERT_GT(nearCount, 0);
  ASSERT_GT(farCount, 0);
  EXPECT_GT(farRow / farCount, 2.0f * nearRow / nearCount) << "distant pixels cover more texels";
}

// Hard edge of the square occluder under a point light (|x|, |z| = 2 on the ground), as in techniques_test.
void expectEdge(const RenderResult& result, float band, const std::string& what) {
  const test::HardEdgeCount count = test::checkHardEdge(result.image, band, 1e-6f);
  EXPECT_GT(count.shadowed + count.lit, 5000) << what;
  EXPECT_EQ(count.wrong, 0) << what;
}

// The widest reach under auto (the default) grows with the map, so that it holds the same width in the scene:
// --pcss-max-radius is a 32nd of the map's side, at least 64 texels; --pcf-max-radius (pcf's and pssm's auto kernel) a
// 64th, at least 16. Each renders the same frame as its explicit count at 512^2 .. 4096^2, under a light large enough
// that the reach matters (the penumbrae are wider than 32 texels at 1024^2): a smaller reach darkens differently.
TEST_F(PcfTechniques, MaxRadiusAutoGrowsWithTheMap) {
  const Scene scene = test::squareOverPlane();
  Camera camera = test::topDown();
  camera.width = 96, camera.height = 72;
  const Light light = parseLight("spot:0,4,0:0,0,0:120:1.5");
  struct Case {
    const char *technique, *param;
    std::vector<std::pair<int, const char*>> sameAs;   // map size, the explicit reach auto equals there
    std::vector<std::pair<int, const char*>> shorter;  // map size, a shorter reach that differs there
  };
  const std::vector<Case> cases = {
      {"pcss",
       "pcss-max-radius",
       {{512, "64"}, {1024, "64"}, {2048, "64"}, {4096, "128"}},
       {{4096, "64"}, {1024, "32"}}},
      {"pcf", "pcf-max-radius", {{512, "16"}, {1024, "16"}, {2048, "32"}, {4096, "64"}}, {{4096, "16"}, {2048, "16"}}},
      {"pssm", "pcf-max-radius", {{1024, "16"}, {4096, "64"}}, {{4096, "16"}}},
  };
  for (const Case& c : cases) {
    const TechniqueInfo& info = findTechnique(c.technique);
    EXPECT_TRUE(Params(info.params).isAuto(c.param)) << c.technique;
    auto visibility = [&](int size, const char* radius) {
      Params params(info.params);
      params.set("map-size", std::to_string(size));
      params.set(c.param, radius);
      Renderer renderer(ctx(), scene);
      return renderer.render(camera, light, info, params).image.require("visibility.Y").data;
    };
    for (const auto& [size, radius] : c.sameAs)
      EXPECT_EQ(visibility(size, "auto"), visibility(size, radius)) << c.technique << " " << size;
    for (const auto& [size, radius] : c.shorter)
      EXPECT_NE(visibility(size, "auto"), visibility(size, radius))
          << c.technique << " " << size << ": " << radius << " texels are too short under this light";
  }
}

// --pcss-search adaptive: where the pyramid says nothing in the search region lies in front of the receiver
// (blocker.Z = -1) the full search finds no blocker either (exactly lit); the early-out takes most lit pixels; and the
// narrowed region's taps come closer to brute-force PCSS (64 x 64 taps) than the full region's at the same count.
TEST_F(PcfTechniques, PcssAdaptiveSearchSkipsOnlyWhatCannotBlockAndSamplesCloser) {
  const Scene scene = test::squareOverPlane();
  Camera camera = test::topDown();
  camera.width = 160, camera.height = 120;
  const TechniqueInfo& pcss = findTechnique("pcss");
  for (const char* spec : {"spot:0,4,0:0,0,0:120:0.4", "dir:0.3,-1,0.2:3"}) {
    const Light light = parseLight(spec);
    auto render = [&](const char* search, const char* taps) {
      Params params(pcss.params);
      params.set("map-size", "512");
      params.set("pcss-search", search);
      params.set("pcss-search-taps", taps);
      params.set("pcss-filter-taps", taps);
      Renderer renderer(ctx(), scene);
      return renderer.render(camera, light, pcss, params).image;
    };
    const Image full = render("full", "8"), adaptive = render("adaptive", "8"), brute = render("full", "64");
    const auto& a = adaptive.require("A").data;
    const auto &skipped = adaptive.require("blocker.Z").data, &fullBlocker = full.require("blocker.Z").data;
    const auto &vf = full.require("visibility.Y").data, &va = adaptive.require("visibility.Y").data;
    const auto& vb = brute.require("visibility.Y").data;
    size_t early = 0, lit = 0;
    double errorFull = 0, errorAdaptive = 0;
    for (size_t i = 0; i < a.size(); ++i) {
      if (a[i] == 0.0f) continue;
      lit += vf[i] == 1.0f;
      if (skipped[i] == -1.0f) {
        ++early;
        EXPECT_EQ(va[i], 1.0f) << spec << " pixel " << i;
        EXPECT_EQ(vf[i], 1.0f) << spec << " pixel " << i;
        EXPECT_EQ(fullBlocker[i], 0.0f) << spec << " pixel " << i;
      }
      errorFull += std::abs(vf[i] - vb[i]), errorAdaptive += std::abs(va[i] - vb[i]);
    }
    EXPECT_GT(early, lit / 2) << spec << ": the pyramid skips most lit pixels";
    EXPECT_LE(errorAdaptive, errorFull * 1.02) << spec;  // measured below or equal (docs/techniques/sm-pcf-pcss.md)
    std::printf("  %s: %zu of %zu lit pixels skipped; mean |pcss - brute force| full %.5f adaptive %.5f\n", spec, early,
                lit, errorFull / a.size(), errorAdaptive / a.size());
  }
}

// --pcss-umbra on (the default): a pixel whose every search tap blocks and whose filter square the pyramid finds wholly
// in front of its strictest comparison is left at 0 without the filter. The frames equal --pcss-umbra off's bit for
// bit (visibility and blocker.Z) on scenes with wide umbrae under spot disks, a sun disk and an alpha-tested caster,
// at grid and Poisson taps; each has umbra pixels for the test to find.
TEST_F(PcfTechniques, PcssUmbraTestLeavesEveryPixelAsTheFilterWould) {
  struct Case {
    const char* scene;
    const char* light;  // "": the scene's own
    const char* pattern;
  };
  for (const Case& c : {Case{"box", "", "poisson"}, Case{"stacked-planes", "spot:0.3,6,0.2:0,0,0:90:1", "poisson"},
                        Case{"staircase", "", "grid"}, Case{"cards", "", "poisson"},
                        Case{"box", "dir:0.3,-1,0.2:2", "poisson"}}) {
    const Scene scene = makeProcedural(c.scene);
    Camera camera = scene.cameras.empty() ? test::topDown() : scene.cameras.front();
    camera.width = 160, camera.height = 90;
    const Light light = *c.light != '\0' ? parseLight(c.light) : scene.lights.front();
    const RenderResult on = render(scene, camera, light, "pcss", {{"pcss-pattern", c.pattern}});
    const RenderResult off = render(scene, camera, light, "pcss", {{"pcss-pattern", c.pattern}, {"pcss-umbra", "off"}});
    for (const char* channel : {"visibility.Y", "blocker.Z"})
      EXPECT_EQ(on.image.require(channel).data, off.image.require(channel).data) << c.scene << " " << channel;
    const auto &v = on.image.require("visibility.Y").data, &a = on.image.require("A").data;
    size_t umbra = 0;
    for (size_t i = 0; i < v.size(); ++i) umbra += a[i] > 0.0f && v[i] == 0.0f;
    EXPECT_GT(umbra, v.size() / 50) << c.scene << " " << c.light;
  }
}

// builtin:staircase under its area light at 320x180 and the Embree reference at 256 spp over its covered pixels whose
// side seen by the camera faces the light (lit.Y): the MAE of a technique at a fixed map size there.
class StaircaseTruth {
 public:
  explicit StaircaseTruth(Context& ctx)
      : ctx_(ctx), scene_(makeProcedural("staircase")), light_(scene_.lights.front()) {
    camera_ = scene_.cameras.front();
    camera_.width = 320, camera_.height = 180;
    const Image first = render("sm", 1024, {});
    const auto& a = first.require("A").data;
    std::vector<reference::ShadowPoint> points;
    for (size_t i = 0; i < a.size(); ++i) {
      if (a[i] == 0.0f) continue;
      auto at = [&](const char* name) { return first.require(name).data[i]; };
      const glm::vec3 p(at("P.X"), at("P.Y"), at("P.Z")), n(at("N.X"), at("N.Y"), at("N.Z"));
      if (glm::dot(n, camera_.eye - p) * glm::dot(n, light_.position - p) <= 0.0f) continue;
      points.push_back({p, n});
      pixels_.push_back(i);
    }
    EXPECT_GT(points.size(), a.size() / 4);
    reference::TraceSettings settings;
    settings.spp = 256;
    truth_ = reference::ShadowTracer(scene_).trace(points, light_, settings).visibility;
  }
  bool areaLight() const { return light_.isArea(); }
  Image render(const std::string& technique, int size, const test::Values& values) {
    const TechniqueInfo& info = findTechnique(technique);
    Params params(info.params);
    params.set("map-size", std::to_string(size));
    for (const auto& [name, value] : values) params.set(name, value);
    Renderer renderer(ctx_, scene_);
    return renderer.render(camera_, light_, info, params).image;
  }
  double mae(const Image& image) const {
    const auto& v = image.require("visibility.Y").data;
    double sum = 0;
    for (size_t k = 0; k < pixels_.size(); ++k) sum += std::abs(v[pixels_[k]] - truth_[k]);
    return sum / static_cast<double>(pixels_.size());
  }
  double mae(const std::string& technique, int size, const test::Values& values = {}) {
    return mae(render(technique, size, values));
  }

 private:
  Context& ctx_;
  Scene scene_;
  Light light_;
  Camera camera_;
  std::vector<size_t> pixels_;
  std::vector<float> truth_;
};

// --pcss-search-taps / --pcss-filter-taps auto (the defaults): each pixel takes taps from its region's texels, up to
// the -max settings, so a finer map, whose penumbrae span more texels, gets more filter taps where a fixed count
// under-samples them. On the staircase (StaircaseTruth) the auto counts' MAE stays flat from 1024^2 to 4096^2
// (measured 0.00030, 0.00029, 0.00030) and lies well below the fixed 8 x 8's (0.00048, 0.00049 at 2048^2 and 4096^2;
// at 480x270 the fixed count's error rose with the map, 0.00060, 0.00061, 0.00062).
TEST_F(PcfTechniques, PcssAutoTapsGetNoWorseWithTheMap) {
  StaircaseTruth staircase(ctx());
  ASSERT_TRUE(staircase.areaLight());
  const TechniqueInfo& pcss = findTechnique("pcss");
  EXPECT_TRUE(Params(pcss.params).isAuto("pcss-search-taps"));
  EXPECT_TRUE(Params(pcss.params).isAuto("pcss-filter-taps"));
  double previous = staircase.mae("pcss", 1024);
  std::printf("  1024^2: MAE auto %.5f\n", previous);
  for (int size : {2048, 4096}) {
    const double automatic = staircase.mae("pcss", size),
                 fixed = staircase.mae("pcss", size, {{"pcss-search-taps", "8"}, {"pcss-filter-taps", "8"}});
    std::printf("  %d^2: MAE auto %.5f, fixed 8x8 %.5f\n", size, automatic, fixed);
    EXPECT_LE(automatic, previous * 1.05) << size;  // flat within the reference's noise (256 rays a pixel)
    EXPECT_LT(automatic, fixed) << size;
    previous = automatic;
  }
}

// --pcss-sparse-taps on (the default): where a pixel's filter taps each stand for 64 texels or more, each compares the
// texel under it instead of four bilinearly (kernels/shared/shadow_common.h sc_sparse_taps). It changes only those
// filters (the search and its blocker depths are the same bit for bit) and keeps their error within 2 %: on the
// staircase (StaircaseTruth) at 4096^2, whose widest penumbrae span ~100 texels, measured 170 pixels changed and MAE
// 0.000302 against 0.000300; none at 1024^2.
TEST_F(PcfTechniques, PcssSparseTapsKeepTheErrorOfBilinearTaps) {
  StaircaseTruth staircase(ctx());
  for (int size : {1024, 4096}) {
    const Image on = staircase.render("pcss", size, {}),
                off = staircase.render("pcss", size, {{"pcss-sparse-taps", "off"}});
    EXPECT_EQ(on.require("blocker.Z").data, off.require("blocker.Z").data) << size;
    const auto &a = on.require("visibility.Y").data, &b = off.require("visibility.Y").data;
    size_t changed = 0;
    for (size_t i = 0; i < a.size(); ++i) changed += a[i] != b[i];
    const double sparse = staircase.mae(on), bilinear = staircase.mae(off);
    std::printf("  %d^2: MAE sparse %.6f, bilinear %.6f, %zu pixels changed\n", size, sparse, bilinear, changed);
    if (size == 4096) {
      EXPECT_GT(changed, 50u);  // the widest penumbrae take the texel taps
    }
    EXPECT_LE(sparse, bilinear * 1.02 + 1e-6) << size;
  }
}

// --pcf-radius auto (the default): the kernel's half-width follows the penumbra up to --pcf-max-radius (auto: a 64th
// of the map's side, at least 16 texels) while its taps stop at --pcf-radius-max (4) a side, so a finer map keeps the
// kernel's width in the world instead of sharpening the penumbra; pssm's per-split PCF likewise, in texels of split 0.
// On the staircase (StaircaseTruth), measured: pcf 0.00247, 0.00219, 0.00220, 0.00223 at 512^2 .. 4096^2 (7, 14 and 28
// texels wide at the last three); with the width held at the taps' 4 texels (as --pcf-max-radius 4 gives) 0.00354 and
// 0.00473 at 1024^2 and 2048^2, and with the former fixed 16 0.00362 at 4096^2; pssm within 4e-5 of pcf.
TEST_F(PcfTechniques, PcfAutoWidthGetsNoWorseWithTheMap) {
  StaircaseTruth staircase(ctx());
  for (const char* technique : {"pcf", "pssm"}) {
    double previous = staircase.mae(technique, 512);
    std::printf("  %s 512^2: MAE %.5f\n", technique, previous);
    for (int size : {1024, 2048, 4096}) {
      const Image image = staircase.render(technique, size, {});
      const double automatic = staircase.mae(image);
      const char* shorter = size < 4096 ? "4" : "16";
      const double narrow = staircase.mae(technique, size, {{"pcf-max-radius", shorter}});
      std::printf("  %s %d^2: MAE %.5f, width at most %s texels %.5f (%s)\n", technique, size, automatic, shorter,
                  narrow, image.attributes().at("penumbra:pcf-width").c_str());
      EXPECT_LE(automatic, previous * 1.05) << technique << " " << size;
      EXPECT_LT(automatic, narrow) << technique << " " << size;
      previous = automatic;
    }
  }
}

TEST_F(PcfTechniques, PoissonTapsAndTheReceiverFitKeepTheHardEdge) {
  const Scene scene = test::squareOverPlane();
  expectEdge(render(scene, test::topDown(), test::pointAbove(), "pcf",
                    {{"map-size", "1024"}, {"pcf-poisson-taps", "16"}, {"pcf-radius", "2"}}),
             0.08f, "pcf with 16 Poisson taps");
  expectEdge(render(scene, test::topDown(), test::pointAbove(), "sm", {{"map-size", "512"}, {"fit", "scene"}}), 0.08f,
             "sm fitted to the scene");
  const RenderResult fitted =
      render(scene, test::topDown(), test::pointAbove(), "sm", {{"map-size", "512"}, {"fit", "receivers"}});
  expectEdge(fitted, 0.08f, "sm fitted to the receivers");
  EXPECT_NE(fitted.image.attributes().at("penumbra:light-fit").find("receivers"), std::string::npos);
}

}  // namespace techniques_pcf_test
}  // namespace penumbra
