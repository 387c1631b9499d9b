// The stability suite (ctest label `stability`): each known failure mode of shadow mapping gets a scene, a
// metric against the Embree reference (tools/reference/) and an assertion about which techniques fail it and
// which do not; every technique in the registry must also get through every scene (degenerate ones included)
// without crashing and without a NaN or a visibility outside [0, 1]. Small sizes so CI stays fast; the
// numbers each assertion guards are printed (`--gtest_also_run_disabled_tests` is not needed) and recorded in
// the "Stability suite" table of docs/tests.md.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "host/eval/metrics.h"
#include "host/pipeline/renderer.h"
#include "host/scene/procedural.h"
#include "host/techniques/registry.h"
#include "tests/support/cl_test.h"
#include "tests/support/render.h"
#include "tools/reference/reference.h"

namespace penumbra {
namespace stability_test {

using test::Values;

// A failure-mode scene: geometry, a camera, a light, and the reference visibility (traced once).
struct Case {
  Scene scene;
  Camera camera;
  Light light;
  Image reference;
};

class Stability : public test::ClTest {
 protected:
  static Case makeCase(Scene scene, Camera camera, const std::string& light, int spp = 16) {
    Case c{std::move(scene), camera, parseLight(light), {}};
    reference::TraceSettings settings;
    settings.spp = spp;
    c.reference = reference::renderReference(ctx(), c.scene, c.camera, c.light, settings).image;
    return c;
  }

  static Camera sceneCamera(const Scene& scene, int width = 128, int height = 96) {
    Camera camera = scene.cameras.front();
    camera.width = width, camera.height = height;
    return camera;
  }

  // Renders `technique`, checks the output is finite and in range, returns it.
  static RenderResult render(const Case& c, const std::string& technique, const Values& values = {}) {
    Values all = values;
    if (findTechnique(technique).hasParam("map-size")) all.try_emplace("map-size", "512");
    RenderResult result = test::renderWith(ctx(), c.scene, c.camera, c.light, technique, all);
    EXPECT_TRUE(test::saneImage(result.image, technique));
    return result;
  }

  static ErrorMetrics metrics(const RenderResult& ours, const Case& c) {
    return compareImages(ours.image, c.reference);
  }

  // Brightest and mean visibility of ours where the reference is in full shadow (< 0.01) over a 5x5 pixel
  // neighbourhood (so edge aliasing does not count) and the point can receive light at all: light bleeding
  // through occluders.
  struct Umbra {
    float max = 0.0f, mean = 0.0f;
    size_t pixels = 0;
  };
  static Umbra umbra(const RenderResult& ours, const Case& c) {
    const auto &vis = ours.image.require("visibility.Y").data, &ref = c.reference.require("visibility.Y").data,
               &a = c.reference.require("A").data, &lit = c.reference.require(kLitChannel).data;
    Umbra u;
    double sum = 0;
    const int w = c.camera.width, h = c.camera.height;
    auto deep = [&](int x, int y) {
      for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx) {
          const int xx = std::clamp(x + dx, 0, w - 1), yy = std::clamp(y + dy, 0, h - 1);
          const size_t j = static_cast<size_t>(yy) * w + xx;
          if (a[j] == 0.0f || ref[j] >= 0.01f) return false;
        }
      return true;
    };
    for (size_t i = 0; i < vis.size(); ++i) {
      if (lit[i] == 0.0f || !deep(static_cast<int>(i) % w, static_cast<int>(i) / w)) continue;
      u.max = std::max(u.max, vis[i]);
      sum += vis[i];
      ++u.pixels;
    }
    u.mean = u.pixels ? static_cast<float>(sum / static_cast<double>(u.pixels)) : 0.0f;
    return u;
  }

  // Fraction of fully lit reference pixels (> 0.999) that ours darkens below `below`: acne, SAT noise.
  static double darkened(const RenderResult& ours, const Case& c, float below) {
    const auto &vis = ours.image.require("visibility.Y").data, &ref = c.reference.require("visibility.Y").data,
               &a = c.reference.require("A").data, &lit = c.reference.require(kLitChannel).data;
    size_t n = 0, dark = 0;
    for (size_t i = 0; i < vis.size(); ++i) {
      if (a[i] == 0.0f || lit[i] == 0.0f || ref[i] <= 0.999f) continue;
      ++n;
      dark += vis[i] < below;
    }
    return n ? static_cast<double>(dark) / static_cast<double>(n) : 0.0;
  }
};

std::vector<std::string> allTechniques() {
  std::vector<std::string> names;
  for (const TechniqueInfo& info : techniques()) names.push_back(info.name);
  return names;
}

// Light bleeding (stacked planes): the Chebyshev bound lets light through a second occluder. VSM bleeds; the
// bleeding reduction, MSM, EVSM4 and every non-moment technique do not.
TEST_F(Stability, LightBleedingOnStackedPlanes) {
  const Scene scene = makeProcedural("stacked-planes");
  const Case c = makeCase(scene, sceneCamera(scene), "spot:0.6,6,0.4:0,0,0:90");
  std::map<std::string, Umbra> seen;
  for (const std::string& name : allTechniques()) seen[name] = umbra(render(c, name), c);
  seen["vsm+reduction"] = umbra(render(c, "vsm", {{"bleeding-reduction", "0.3"}}), c);
  for (const auto& [name, u] : seen)
    std::printf("  bleeding %-14s umbra pixels %zu max %.4f mean %.5f\n", name.c_str(), u.pixels, u.max, u.mean);
  ASSERT_GT(seen["sm"].pixels, 200u);
  // Fails: the Chebyshev bound over two occluders (measured 0.12 for both; docs/tests.md, "Stability suite").
  EXPECT_GT(seen["vsm"].max, 0.05f);
  EXPECT_GT(seen["savsm"].max, 0.05f);
  // Does not fail: exact depth tests, the stronger moment bounds, layers, and the bleeding reduction.
  for (const char* name : {"sm", "pcf", "pcss", "evsm4", "msm", "vssm", "lvsm", "vsm+reduction"})
    EXPECT_LT(seen[name].max, 0.02f) << name;
}

// Acne at grazing light angles: a plane nothing shadows must stay lit for every technique.
TEST_F(Stability, NoAcneAtGrazingAngles) {
  const Scene scene = makeProcedural("plane");
  for (const char* light : {"dir:1,-0.2,0.3", "spot:6,0.8,0:0,0,0:120"}) {
    const Case c = makeCase(scene, sceneCamera(scene), light, 4);
    for (const std::string& name : allTechniques()) {
      const double dark = darkened(render(c, name), c, 0.99f);
      std::printf("  acne %-8s %-26s darkened %.5f\n", name.c_str(), light, dark);
      EXPECT_LE(dark, 1e-4) << name << " under " << light;
    }
  }
}

// Contact shadows (a box on a floor): no light gap where the box meets the floor.
TEST_F(Stability, ContactShadowsOfABoxOnAFloor) {
  const Scene scene = makeProcedural("box");
  const Case c = makeCase(scene, sceneCamera(scene), scene.lights.front().describe());
  for (const std::string& name : allTechniques()) {
    const RenderResult r = render(c, name);
    const ErrorMetrics m = metrics(r, c);
    const Umbra u = umbra(r, c);
    std::printf("  contact %-8s mae %.5f leak %.5f umbra max %.3f mean %.4f\n", name.c_str(), m.mae, m.leak, u.max,
                u.mean);
    EXPECT_LT(m.leak, 0.002) << name << ": light leaking at the contact line";
    // Measured up to 0.012 (savsm); psvsm's trilinear lookups (--moment-filtering trilinear) reach 0.031 on the
    // grazing floor.
    EXPECT_LT(u.max, 0.05f) << name << ": light inside the box's umbra";
  }
}

// Non-planar receivers (the staircase under a plate, a sun disk): the average-blocker assumptions of PCSS and
// VSSM meet steps; VSSM's subdivision exists for exactly this.
TEST_F(Stability, NonPlanarReceiversOnTheStaircase) {
  const Scene scene = makeProcedural("staircase");
  const Case c = makeCase(scene, sceneCamera(scene), "dir:0.8,-1,0.3:6", 64);
  for (const std::string& name : allTechniques()) {
    const ErrorMetrics m = metrics(render(c, name), c);
    std::printf("  staircase %-8s mae %.5f p95 %.4f leak %.5f false %.5f\n", name.c_str(), m.mae, m.p95, m.leak,
                m.falseShadow);
    EXPECT_LT(m.mae, 0.03) << name;
    EXPECT_LT(m.falseShadow, 0.002) << name;
  }
  const ErrorMetrics flat = metrics(render(c, "vssm", {{"vssm-subdivision", "none"}}), c);
  const ErrorMetrics subdivided = metrics(render(c, "vssm"), c);
  std::printf("  staircase vssm-none mae %.5f\n", flat.mae);
  EXPECT_LT(subdivided.mae, flat.mae) << "kernel subdivision must reduce VSSM's non-planarity error";
}

// PCSS's tap pattern where several blockers overlap (stacked planes) and the receiver is not a plane (staircase),
// under each scene's own area light: the rotated Poisson disk (the default) covers the disk the light subtends, the
// grid a square around it, so the grid's box filter is the wrong shape as well as banded. Measured at 128x96 against
// 256 spp: docs/techniques/sm-pcf-pcss.md has the 480x270 table (the disk at 8x8 taps halves the grid's MAE or more).
TEST_F(Stability, PcssPoissonDiskAgainstTheGridUnderAreaLights) {
  for (const char* name : {"staircase", "stacked-planes"}) {
    const Scene scene = makeProcedural(name);
    const Case c = makeCase(scene, sceneCamera(scene), scene.lights.front().describe(), 256);
    const ErrorMetrics grid = metrics(render(c, "pcss", {{"pcss-pattern", "grid"}}), c);
    const ErrorMetrics disk = metrics(render(c, "pcss"), c);
    std::printf("  pcss %-14s grid mae %.5f umbra light %.4f; poisson mae %.5f umbra light %.4f\n", name, grid.mae,
                grid.umbraLight, disk.mae, disk.umbraLight);
    EXPECT_LT(disk.mae, 0.7 * grid.mae) << name;
    EXPECT_LE(disk.umbraLight, 0.02) << name << ": light let into the umbra";
  }
}

// Thin casters (poles): filtering wider than a pole washes its shadow out.
TEST_F(Stability, ThinCastersKeepTheirShadows) {
  const Scene scene = makeProcedural("poles");
  const Case c = makeCase(scene, sceneCamera(scene), scene.lights.front().describe());
  std::map<std::string, ErrorMetrics> seen;
  for (const std::string& name : allTechniques()) {
    const ErrorMetrics m = seen[name] = metrics(render(c, name), c);
    std::printf("  poles %-8s mae %.5f leak %.5f false %.5f\n", name.c_str(), m.mae, m.leak, m.falseShadow);
  }
  // Does not fail: unfiltered and blocker-adaptive lookups keep 1-2 texel poles.
  EXPECT_LT(seen["sm"].leak, 0.005);
  EXPECT_LT(seen["vssm"].leak, 0.015);
  // Fails: a 5-texel moment blur and PCF's 5x5 kernel wash a 1.3-texel pole's shadow out (measured 0.027, 0.026).
  const ErrorMetrics blurred = metrics(render(c, "vsm", {{"blur-radius", "2"}}), c);
  const ErrorMetrics wide = metrics(render(c, "pcf", {{"pcf-radius", "2"}, {"pcf-adaptive", "on"}}), c);
  std::printf("  poles vsm r=2   mae %.5f leak %.5f; pcf r=2 adaptive mae %.5f leak %.5f\n", blurred.mae, blurred.leak,
              wide.mae, wide.leak);
  EXPECT_GT(blurred.leak, 0.01);
  EXPECT_GT(wide.leak, 0.01);
  // Helps: the auto radius (--blur-radius, --pcf-radius) matches the filter to the sun's narrow penumbrae here
  // (r = 0): under half the leak (measured vsm 0.0080 against 0.027, pcf 0.0022 against 0.026).
  EXPECT_LT(seen["vsm"].leak, 0.5 * blurred.leak);
  EXPECT_LT(seen["pcf"].leak, 0.5 * wide.leak);
}

// SAT precision: a large map over a long depth range; fp32 tables lose the low bits.
TEST_F(Stability, SatPrecisionOverALongDepthRange) {
  const Scene scene = makeProcedural("box", {{"ground", 400}, {"size", 4}});
  Camera camera = sceneCamera(scene);
  const Case c = makeCase(scene, camera, "dir:0.3,-1,0.2", 4);
  std::map<std::string, double> mae;
  for (const char* mode : {"float", "fixed32", "fixed64"}) {
    const RenderResult r = render(c, "savsm", {{"map-size", "2048"}, {"sat-precision", mode}, {"fit", "scene"}});
    const ErrorMetrics m = metrics(r, c);
    const double dark = darkened(r, c, 0.99f);
    mae[mode] = m.mae;
    std::printf("  sat %-8s darkened %.5f mae %.5f p95 %.4f\n", mode, dark, m.mae, m.p95);
    EXPECT_LT(dark, 0.005) << mode;
  }
  // fp32 (even offset to zero mean) loses low bits of the moments over a 2048^2 table: measurably worse than
  // the exact integer tables (measured MAE 0.0045 vs 0.0013).
  EXPECT_GT(mae["float"], 1.2 * mae["fixed64"]);
  EXPECT_NEAR(mae["fixed32"], mae["fixed64"], 0.1 * mae["fixed64"]);
}

// Half moment storage (--moment-storage fp16) where it is weakest: a long depth range (a 400-unit ground) squeezes
// the scene's depths into few half steps, and the exponents drop to 5.54 (EVSM) and 8 (ESM; fp32's auto picks more).
TEST_F(Stability, HalfMomentStorage) {
  const Scene scene = makeProcedural("box", {{"ground", 400}, {"size", 4}});
  const Case c = makeCase(scene, sceneCamera(scene), "dir:0.3,-1,0.2", 4);
  const Scene stacked = makeProcedural("stacked-planes");
  const Case s = makeCase(stacked, sceneCamera(stacked), "spot:0.6,6,0.4:0,0,0:90");
  std::map<std::string, ErrorMetrics> seen;
  std::map<std::string, float> bleeding;
  for (const char* name : {"vsm", "evsm2", "evsm4", "esm", "msm", "psvsm"})
    for (const char* storage : {"fp32", "fp16"}) {
      const std::string key = std::string(name) + "/" + storage;
      // blur-radius 2 for every technique: the storage compared at one filter (auto would pick each its own).
      const RenderResult r =
          render(c, name, {{"map-size", "2048"}, {"fit", "scene"}, {"moment-storage", storage}, {"blur-radius", "2"}});
      const ErrorMetrics m = seen[key] = metrics(r, c);
      const double dark = darkened(r, c, 0.99f);
      bleeding[key] = umbra(render(s, name, {{"moment-storage", storage}}), s).max;
      std::printf("  half %-12s darkened %.5f mae %.5f leak %.5f | stacked-planes umbra max %.4f\n", key.c_str(), dark,
                  m.mae, m.leak, bleeding[key]);
      EXPECT_LT(dark, 0.005) << key << ": acne on the lit ground";  // measured <= 0.0043, fp32 and fp16 alike
    }
  // Does not fail: half rounding costs vsm, evsm2 and evsm4 no accuracy here (measured fp16/fp32 MAE 0.79-1.0).
  for (const char* name : {"vsm", "evsm2", "evsm4"})
    EXPECT_LT(seen[std::string(name) + "/fp16"].mae, 1.1 * seen[std::string(name) + "/fp32"].mae) << name;
  EXPECT_LT(bleeding["evsm4/fp16"], 0.02f) << "evsm4's negative warp still stops the bleeding at c = 5.54";
  // Fails: ESM at c = 8 is a soft step that leaks (measured leak 0.0111 vs 0.0080 at fp32's auto exponent, 0.0059 at
  // the fixed 80 before it, and 0.076 of light in the stacked planes' umbra vs 0); MSM's moment bias of 1e-3 (vs
  // 3e-5) widens its penumbrae (MAE 0.0067 vs 0.0047).
  EXPECT_GT(seen["esm/fp16"].leak, 1.2 * seen["esm/fp32"].leak);
  EXPECT_GT(bleeding["esm/fp16"], 0.01f);
  EXPECT_GT(seen["msm/fp16"].mae, 1.2 * seen["msm/fp32"].mae);
  // Fails since auto splits are the default: psvsm picks 2 splits here, the far one spanning 20-254 units in one
  // 2048^2 map, whose depths half storage rounds coarsely (measured MAE 0.00231 vs 0.00065; with trilinear lookups
  // 0.00264 vs 0.00191, and 1.0x with 4 splits).
  EXPECT_GT(seen["psvsm/fp16"].mae, 1.2 * seen["psvsm/fp32"].mae);
}

// A point light inside a closed box (all six cube faces; the walls 0.5 from the light, the ground up to 6.5 away): the
// box hides the light from the ground around it, for every technique (measured mean ground visibility: lvsm and esm
// 4e-4, pcss 3e-4, the others below 1e-4; psvsm's trilinear lookups 0.0057).
TEST_F(Stability, APointLightInsideAClosedBox) {
  const Scene scene = makeProcedural("box");
  const Case c = makeCase(scene, sceneCamera(scene), "point:0,0.5,0:0.05");
  std::map<std::string, double> seen;
  for (const std::string& name : allTechniques()) {
    const RenderResult r = render(c, name);
    const auto &vis = r.image.require("visibility.Y").data, &ref = c.reference.require("visibility.Y").data;
    const auto &a = r.image.require("A").data, &py = r.image.require("P.Y").data;
    const auto &px = r.image.require("P.X").data, &pz = r.image.require("P.Z").data;
    double sum = 0;
    size_t ground = 0;
    for (size_t i = 0; i < vis.size(); ++i) {
      if (a[i] == 0.0f || py[i] > 1e-3f || std::max(std::abs(px[i]), std::abs(pz[i])) < 0.6f) continue;
      ASSERT_EQ(ref[i], 0.0f) << "the reference: the box encloses the light";
      sum += vis[i], ++ground;
    }
    ASSERT_GT(ground, 1000u);
    seen[name] = sum / static_cast<double>(ground);
    std::printf("  closed box %-8s mean ground visibility %.5f\n", name.c_str(), seen[name]);
  }
  for (const auto& [name, mean] : seen) EXPECT_LT(mean, 0.01) << name;
}

// Issue 20's targets on every built-in scene under its own area light (each has one), default parameters, against
// 256 spp: some technique reaches MAE <= kBestMaxMae on every scene; vssm stays within kVssmOverPcss of the MAE of
// pcss with fixed 8 x 8 taps, the configuration the ratio was set against (pcss's per-pixel tap counts, the default
// since, took its own error on staircase from 0.00060 to 0.00040, which vssm's 0.00045 is 1.12x; vssm's error did not
// change) (measured 0.47-0.86 here since VSSM's narrowed search and stacked-blocker fallbacks; 0.48-0.92 since
// --map-size auto sizes vssm's map for 24 texels across the narrow end of its penumbrae; 0.65-1.05 and box 1.098 at the
// 2048^2 floor before, which kVssmOverPcssBox guards with room for another device's rounding; 1.24-1.63 at the pixels'
// need alone), since its disk kernels (--vssm-disk-strips 8; the paper's squares were 1.8-2.1x), the receivers' exact
// depth slope and the sin-scaled normal offset (1.16-1.29 on box and stacked-planes before: docs/techniques/README.md,
// "The normal offset"); and every technique keeps light out of the umbra (umbra_light <= kMaxUmbraLight; measured worst
// 0.045, psvsm on poles). Held since the auto radii, savsm's auto occluder distance, esm's auto exponent and --map-size
// auto as the default (the poles' pixels need 4096^2: pcss 0.056 at 2048^2, 0.019 now; before the auto radii pcf had
// 0.74 on poles and 0.31 on cards, the moment techniques 0.5-0.7, the split techniques 0.36-0.51, savsm 0.19 and esm
// 0.22 at c = 80 on poles). docs/evaluation.md ("Targets on the built-in scenes").
constexpr double kBestMaxMae = 0.004;
constexpr double kMaxUmbraLight = 0.05;
constexpr double kVssmOverPcss = 1.1;
constexpr double kVssmOverPcssBox = 1.15;

TEST_F(Stability, TargetsOnEveryBuiltinSceneUnderItsAreaLight) {
  for (const ProceduralInfo& builtin : proceduralScenes()) {
    const Scene scene = makeProcedural(builtin.name);
    ASSERT_FALSE(scene.lights.empty()) << builtin.name;
    const Light& light = scene.lights.front();
    ASSERT_TRUE(light.radius > 0.0f || light.angularRadiusDeg > 0.0f) << builtin.name << ": not an area light";
    const Case c = makeCase(scene, sceneCamera(scene, 240, 135), light.describe(), 256);
    std::map<std::string, ErrorMetrics> seen;
    for (const std::string& name : allTechniques()) {
      // The techniques' own map sizes (the suite's 512 elsewhere is for speed): the targets are the defaults'.
      const TechniqueInfo& info = findTechnique(name);
      Values own;
      if (info.hasParam("map-size")) {
        const Params defaults(info.params);
        own["map-size"] = defaults.isAuto("map-size") ? "auto" : std::to_string(defaults.getInt("map-size"));
      }
      seen[name] = metrics(render(c, name, own), c);
    }
    std::string best, worst;
    for (const auto& [name, m] : seen) {
      if (best.empty() || m.mae < seen[best].mae) best = name;
      if (worst.empty() || m.umbraLight > seen[worst].umbraLight) worst = name;
    }
    Values fixedTaps{{"map-size", "auto"}, {"pcss-search-taps", "8"}, {"pcss-filter-taps", "8"}};
    const ErrorMetrics pcss8 = metrics(render(c, "pcss", fixedTaps), c);
    const ErrorMetrics &pcss = seen["pcss"], &vssm = seen["vssm"];
    std::printf(
        "  targets %-15s best %-8s mae %.5f; pcss mae %.5f (8x8 %.5f) umbra light %.4f; vssm / pcss 8x8 %.3f; "
        "worst umbra light %-8s %.4f (of %zu umbra pixels)\n",
        builtin.name.c_str(), best.c_str(), seen[best].mae, pcss.mae, pcss8.mae, pcss.umbraLight,
        pcss8.mae > 0 ? vssm.mae / pcss8.mae : 1.0, worst.c_str(), seen[worst].umbraLight, pcss.umbraPixels);
    EXPECT_LE(seen[best].mae, kBestMaxMae) << builtin.name;
    for (const auto& [name, m] : seen) {  // every technique
      EXPECT_LE(m.umbraLight, kMaxUmbraLight) << builtin.name << " " << name << ": light let into the umbra";
    }
    if (pcss8.mae > 1e-5) {
      EXPECT_LE(vssm.mae, (builtin.name == "box" ? kVssmOverPcssBox : kVssmOverPcss) * pcss8.mae) << builtin.name;
    }
  }
}

// Issue 36, item 4: occluders stacked inside one kernel (stacked-planes under a light of radius 2, 3 and 4, so a
// ground pixel's kernels hold both plates) spread VSSM's moments: the Chebyshev bound let light into the umbra and
// eq. 4 put the blocker too near the light (25 % and 80 % of the umbra pixels above 0.1 at 480x270 under radius 2 and
// 3: docs/techniques/vssm.md, "Stacked occluders"). The penumbra kernel's HSM range and the stacked-blocker fallbacks
// of the search and the shading keep it at most kMaxUmbraLight under radius 2 and 3; under radius 4 the fallback's
// blocker average (PCSS's) still lets light in (8 % at 480x270, pcss 7 % with --pcss-stacked-trace off), and tracing
// the stacked kernels' segments through the map (--vssm-stacked-trace, --pcss-stacked-trace) removes it. Without the
// fallbacks (--vssm-stacked 0), and under radius 4 without the trace, the scene does fail, so it tests what it claims
// to.
TEST_F(Stability, StackedOccludersKeepLightOutOfVssmUmbra) {
  const Scene scene = makeProcedural("stacked-planes");
  for (const char* light : {"spot:0.3,6,0.2:0,0,0:90:2", "spot:0.3,6,0.2:0,0,0:90:3", "spot:0.3,6,0.2:0,0,0:90:4"}) {
    const bool widest = std::string(light).back() == '4';
    const Case c = makeCase(scene, sceneCamera(scene, 240, 135), light, 256);
    const ErrorMetrics on = metrics(render(c, "vssm", {{"map-size", "auto"}}), c);
    const ErrorMetrics off = metrics(render(c, "vssm", {{"map-size", "auto"}, {"vssm-stacked", "0"}}), c);
    const ErrorMetrics untraced = metrics(render(c, "vssm", {{"map-size", "auto"}, {"vssm-stacked-trace", "off"}}), c);
    const ErrorMetrics pcss = metrics(render(c, "pcss", {{"map-size", "auto"}}), c);
    std::printf(
        "  stacked occluders, %s: vssm umbra light %.4f (mae %.5f), --vssm-stacked 0 %.4f (mae %.5f), "
        "--vssm-stacked-trace off %.4f (mae %.5f), pcss %.4f of %zu umbra pixels\n",
        light, on.umbraLight, on.mae, off.umbraLight, off.mae, untraced.umbraLight, untraced.mae, pcss.umbraLight,
        on.umbraPixels);
    ASSERT_GT(on.umbraPixels, 500u) << light;
    EXPECT_LE(on.umbraLight, kMaxUmbraLight) << light;
    EXPECT_GT(off.umbraLight, 2 * kMaxUmbraLight) << light;
    EXPECT_LT(on.mae, off.mae) << light;
    EXPECT_LE(on.mae, untraced.mae) << light;
    if (widest) {
      EXPECT_GT(untraced.umbraLight, kMaxUmbraLight) << light;
    }
    EXPECT_LE(pcss.umbraLight, kMaxUmbraLight) << light;
  }
}

// Degenerate inputs: every technique gets through them cleanly (render() checks NaN and range).
TEST_F(Stability, DegenerateScenesNeverCrashOrEmitNan) {
  Camera camera;
  camera.eye = {0, 2, 5}, camera.target = {0, 0, 0}, camera.width = 48, camera.height = 32;
  std::vector<std::pair<std::string, Case>> cases;
  const Scene triangle = makeProcedural("single-triangle");
  cases.emplace_back("single triangle", Case{triangle, camera, parseLight("spot:0,0,4:0,0,0:60:0.2"), {}});
  const Scene box = makeProcedural("box");
  cases.emplace_back("light inside the box", Case{box, camera, parseLight("spot:0,0.5,0:0,0,0:120:0.05"), {}});
  cases.emplace_back("point light inside the box", Case{box, camera, parseLight("point:0,0.5,0:0.05"), {}});
  cases.emplace_back("point light on the ground", Case{box, camera, parseLight("point:1.5,0,1.5"), {}});
  Camera away = camera;
  away.target = {0, 2, 10};
  cases.emplace_back("camera looking away", Case{box, away, parseLight("dir:0,-1,0:2"), {}});
  Scene empty;
  cases.emplace_back("empty scene", Case{empty, camera, parseLight("dir:0,-1,0"), {}});
  for (const auto& [what, c] : cases)
    for (const std::string& name : allTechniques()) {
      SCOPED_TRACE(what + " / " + name);
      const RenderResult r = render(c, name);
      if (what == "empty scene" || what == "camera looking away") {
        for (float v : r.image.require("visibility.Y").data) ASSERT_EQ(v, 1.0f) << "nothing seen: all lit";
      }
    }
}

}  // namespace stability_test
}  // namespace penumbra
