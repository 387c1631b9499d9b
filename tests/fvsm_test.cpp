// Fitted virtual shadow maps (`fvsm`, host/techniques/fvsm.cpp): against uniform maps of the same finest texel under
// the exact hard-shadow reference, the texel budget, the quality parameter, the page table's coverage, and the
// tile views' crop.
#include <gtest/gtest.h>

#include <cstdio>
#include <regex>
#include <string>

#include "host/eval/metrics.h"
#include "host/scene/procedural.h"
#include "host/views/views.h"
#include "tests/support/cl_test.h"
#include "tests/support/render.h"
#include "tools/reference/reference.h"

namespace penumbra {
namespace fvsm_test {

using test::renderWith;

class Fvsm : public test::ClTest {};

// The texels an fvsm frame drew, from its header.
uint64_t texelsDrawn(const RenderResult& r) {
  const std::string& a = r.image.attributes().at("penumbra:fvsm");
  std::smatch m;
  EXPECT_TRUE(std::regex_search(a, m, std::regex("([0-9]+) texels drawn"))) << a;
  return m.empty() ? 0 : std::stoull(m[1]);
}

// A low camera over the poles looking down the field under a hard sun: magnification near, minification far, so
// receivers need very different resolutions across the map.
struct Case {
  Scene scene = makeProcedural("poles");
  Camera camera;
  Light light;
  Case() {
    camera.eye = {0.4f, 1.16f, -4.4f}, camera.target = {0.0f, 0.8f, -10.0f}, camera.fovYDeg = 50.0f;
    camera.width = 480, camera.height = 270;
    light = parseLight("dir:0.6,-1,-0.3");
  }
};

// Luksch's wrong pixels: covered, lit-mask pixels off by more than 0.1 against the exact reference.
double wrong(const RenderResult& ours, const reference::ReferenceResult& ref) {
  return compareImages(ours.image, ref.image).off;
}

// The test: fvsm renders fewer texels than a uniform map of equal wrong-pixel count. The smallest uniform map
// (sm, 1024 .. 8192) with no more wrong pixels than fvsm's needs more texels than fvsm drew (measured on PoCL at
// 480x270: fvsm 0.119 % wrong with 3.0 M texels; sm 8192^2 0.088 %, 4096^2 0.137 %, 2048^2 0.346 %: 22x the
// texels for equal accuracy). Quality 2 (two texels a pixel step) is more accurate and near the 0.1 %
// (measured 0.096 % with 6.6 M texels; the limit leaves 20 % for other devices' rounding of edge pixels).
TEST_F(Fvsm, FewerTexelsThanAUniformMapOfEqualWrongPixels) {
  const Case c;
  const reference::ReferenceResult ref = reference::renderReference(ctx(), c.scene, c.camera, c.light, {});
  // The tiles alone: exact edges (below) decide edge pixels by their rays, which no uniform map does.
  const test::Values values = {
      {"map-size", "256"}, {"fvsm-max-size", "8192"}, {"fvsm-budget", "1e9"}, {"exact-edges", "off"}};
  const RenderResult fvsm = renderWith(ctx(), c.scene, c.camera, c.light, "fvsm", values);
  ASSERT_TRUE(test::saneImage(fvsm.image, "fvsm"));
  const std::string header = fvsm.image.attributes().at("penumbra:fvsm");
  ASSERT_NE(header.find("..5 of 5"), std::string::npos) << header;  // the deepest level is used
  const double wf = wrong(fvsm, ref);
  uint64_t uniform = 0;
  for (int size : {1024, 2048, 4096, 8192}) {
    const double wu =
        wrong(renderWith(ctx(), c.scene, c.camera, c.light, "sm", {{"map-size", std::to_string(size)}}), ref);
    std::printf("sm %d: %.4f%% wrong\n", size, 100 * wu);
    if (wu <= wf && uniform == 0) uniform = static_cast<uint64_t>(size) * size;
  }
  if (uniform == 0) uniform = uint64_t{8192} * 8192;  // no uniform map reaches fvsm: compare with the largest
  std::printf("fvsm %.4f%% wrong with %llu texels (%s)\n", 100 * wf, static_cast<unsigned long long>(texelsDrawn(fvsm)),
              header.c_str());
  EXPECT_LT(texelsDrawn(fvsm) * 4, uniform);
  test::Values finer = values;
  finer["fvsm-quality"] = "2";
  const RenderResult fine = renderWith(ctx(), c.scene, c.camera, c.light, "fvsm", finer);
  std::printf("fvsm quality 2: %.4f%% wrong with %llu texels\n", 100 * wrong(fine, ref),
              static_cast<unsigned long long>(texelsDrawn(fine)));
  EXPECT_LT(wrong(fine, ref), wf);
  EXPECT_LE(wrong(fine, ref), 0.0012);
}

// Thin casters under a low sun (issue 36, item 8): 0.03-wide poles whose shadows are streaks a pixel or two wide
// down the field. The tiles alone get a pixel wrong wherever its centre and its nearest texel's centre fall on
// opposite sides of a streak's edge (0.16 % at 1280x720; four times the texels a pixel step still leave 0.09 %), and a
// pole thinner than a texel shows in some texels only. Exact edges test those pixels' rays against the triangles of
// their texels and those triangles' neighbours in the index buffer (a thin box's other faces), and every pixel they
// change becomes the reference's. Measured on PoCL at 480x270: poles 0.335 % wrong without, none with (556 pixels
// changed); alpha-tested cards with round holes (the alpha test on those rays too) 0.29 % and none; the staircase
// under a hard spot (a perspective map) 0.012 % and none. Without the neighbours the poles kept 0.035 %, 11 of the
// changed pixels unlike the reference.
TEST_F(Fvsm, ExactEdgesDecideThinCastersAndMasksAsTheReference) {
  struct Lit {
    const char* scene;
    const char* light;
    double onAtMost;      // wrong share with exact edges
    double unlikeAtMost;  // share of the changed pixels that are not the reference's
  };
  for (const Lit& lit :
       {Lit{"poles:thickness=0.03", "dir:1,-0.18,0.4", 0.0002, 0.01}, Lit{"cards", "dir:0.3,-1,0.25", 0.0002, 0.01},
        Lit{"staircase", "spot:0.2,6,0.3:0,0,0:70", 0.0002, 0.01}}) {
    const Scene scene = makeProceduralFromSpec(lit.scene);
    Camera camera = scene.cameras.front();
    camera.width = 480, camera.height = 270;
    const Light light = parseLight(lit.light);
    const reference::ReferenceResult ref = reference::renderReference(ctx(), scene, camera, light, {});
    const RenderResult off = renderWith(ctx(), scene, camera, light, "fvsm", {{"exact-edges", "off"}});
    const RenderResult on = renderWith(ctx(), scene, camera, light, "fvsm", {{"exact-edges", "on"}});
    ASSERT_TRUE(test::saneImage(on.image, lit.scene));
    const double wrongOff = wrong(off, ref), wrongOn = wrong(on, ref);
    const auto& a = off.image.require("visibility.Y").data;
    const auto& b = on.image.require("visibility.Y").data;
    const auto& exact = ref.image.require("visibility.Y").data;
    size_t changed = 0, unlike = 0;
    for (size_t i = 0; i < a.size(); ++i)
      if (a[i] != b[i]) ++changed, unlike += b[i] != exact[i];
    std::printf(
        "%s under %s: %.4f%% wrong without exact edges, %.4f%% with; %zu pixels changed, %zu unlike the "
        "reference\n",
        lit.scene, lit.light, 100 * wrongOff, 100 * wrongOn, changed, unlike);
    EXPECT_LE(wrongOn, lit.onAtMost) << lit.scene;
    EXPECT_LT(wrongOn * 4, wrongOff) << lit.scene;
    EXPECT_GT(changed, 10u) << lit.scene;
    EXPECT_LE(static_cast<double>(unlike), lit.unlikeAtMost * static_cast<double>(changed)) << lit.scene;
  }
}

// Over the budget the tiles serving the most undersampled pixels are refined first; the rest stay coarser, the
// header counts them, and the frame stays within the budget and sane.
TEST_F(Fvsm, BudgetCoarsensGracefully) {
  const Case c;
  const test::Values base = {{"map-size", "256"}, {"fvsm-max-size", "8192"}};
  test::Values tight = base, loose = base;
  tight["fvsm-budget"] = std::to_string(4 * 256 * 256);
  loose["fvsm-budget"] = "1e9";
  const RenderResult a = renderWith(ctx(), c.scene, c.camera, c.light, "fvsm", tight);
  const RenderResult b = renderWith(ctx(), c.scene, c.camera, c.light, "fvsm", loose);
  ASSERT_TRUE(test::saneImage(a.image, "tight"));
  EXPECT_LE(texelsDrawn(a), uint64_t{4} * 256 * 256);
  EXPECT_GT(texelsDrawn(b), texelsDrawn(a));
  EXPECT_NE(a.image.attributes().at("penumbra:fvsm").find("coarser than they need"), std::string::npos);
  EXPECT_EQ(b.image.attributes().at("penumbra:fvsm").find("coarser than they need"), std::string::npos);
  const reference::ReferenceResult ref = reference::renderReference(ctx(), c.scene, c.camera, c.light, {});
  EXPECT_GE(wrong(a, ref), wrong(b, ref));
}

// A lower quality xi draws no more texels; outlier rejection refines no more than keeping every pixel's need.
TEST_F(Fvsm, QualityAndOutliersTradeTexelsForAccuracy) {
  const Case c;
  const test::Values base = {{"map-size", "256"}, {"fvsm-max-size", "8192"}, {"fvsm-budget", "1e9"}};
  uint64_t previous = 0;
  for (const char* quality : {"0.25", "1", "4"}) {
    test::Values v = base;
    v["fvsm-quality"] = quality;
    const uint64_t texels = texelsDrawn(renderWith(ctx(), c.scene, c.camera, c.light, "fvsm", v));
    EXPECT_GE(texels, previous) << quality;
    previous = texels;
  }
  test::Values none = base, some = base;
  none["fvsm-outliers"] = "0", some["fvsm-outliers"] = "0.2";
  EXPECT_LE(texelsDrawn(renderWith(ctx(), c.scene, c.camera, c.light, "fvsm", some)),
            texelsDrawn(renderWith(ctx(), c.scene, c.camera, c.light, "fvsm", none)));
}

// Under a sun every covered pixel lies in the fitted base map, so the page table gives each a tile (level.Y >= 0);
// every builtin scene renders sane.
TEST_F(Fvsm, EveryCoveredPixelFindsATile) {
  const Case c;
  const RenderResult r = renderWith(ctx(), c.scene, c.camera, c.light, "fvsm", {{"map-size", "256"}});
  const auto& level = r.image.require("level.Y").data;
  const auto& alpha = r.image.require("A").data;
  size_t covered = 0;
  for (size_t i = 0; i < level.size(); ++i)
    if (alpha[i] > 0.0f) {
      ++covered;
      EXPECT_GE(level[i], 0.0f) << i;
    }
  EXPECT_GT(covered, 10000u);
  for (const ProceduralInfo& info : proceduralScenes()) {
    const Scene s = makeProcedural(info.name);
    Camera cam = s.cameras.front();
    cam.width = 96, cam.height = 64;
    ASSERT_TRUE(
        test::saneImage(renderWith(ctx(), s, cam, s.lights.front(), "fvsm", {{"map-size", "128"}}).image, info.name));
  }
}

// A crop of the base window maps the part's corners onto the crop's NDC corners (perspective and orthographic) with
// texel widths scaled by the part.
TEST(FvsmCrop, TilesMapTheirPartOntoTheirWholeMap) {
  Scene scene = makeProcedural("box");
  for (const char* spec : {"spot:-2,5,-1:0,0,0:60", "dir:0.3,-1,0.2"}) {
    const LightView base = fitLightView(parseLight(spec), scene.bounds(), 1024);
    const glm::vec2 lo(-0.5f, 0.25f), hi(0.0f, 0.75f);
    const LightView part = cropLightView(base, lo, hi, 512);
    EXPECT_EQ(part.gpu.width, 512);
    EXPECT_FLOAT_EQ(part.gpu.texelScale, base.gpu.texelScale * 1024.0f / 512.0f * 0.25f) << spec;
    const glm::mat4 inv = glm::inverse(base.raster.projection * base.raster.view);
    for (const glm::vec2 corner : {lo, hi, glm::vec2(lo.x, hi.y)}) {
      glm::vec4 w = inv * glm::vec4(corner, 0.3f, 1.0f);
      w /= w.w;
      const glm::vec4 c = part.raster.projection * part.raster.view * w;
      const glm::vec2 ndc = glm::vec2(c) / c.w;
      EXPECT_NEAR(ndc.x, corner.x == lo.x ? -1.0f : 1.0f, 1e-4f) << spec;
      EXPECT_NEAR(ndc.y, corner.y == lo.y ? -1.0f : 1.0f, 1e-4f) << spec;
    }
  }
}

}  // namespace fvsm_test
}  // namespace penumbra
