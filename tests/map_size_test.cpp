// The sizes chosen per frame from the camera's pixels. --map-size auto (host/pipeline/map_size.h,
// host/views/light_fit.h neededMapSize, kernels/fit.cl fit_size_partial): the device histogram's quantiles against a
// plain C++ reference of the same measure on a G-buffer with a spacing that varies across it, background, NaN and
// out-of-map pixels among them; the analytic need of a uniform grid; the renderer choosing larger maps for larger
// frames, for spot and point lights; the needs measured on the drawn probe (narrower penumbrae and thinner casters ask
// for larger maps; the caster-detail histogram of fit_detail_partial against a C++ reference on bars, nested bars,
// ramps, NaN, 1x1 and odd-sized maps); the parameter's text form, and the techniques that refuse it. --blur-radius auto
// and --pcf-radius auto (host/techniques/shadow_map.h autoRadiusParams, measurePenumbraWidth, fit_penumbra_partial),
// savsm's --savsm-occluder-distance auto (measureOccluderDistance): the penumbra histogram's quantiles of widths and
// distances against a C++ reference on the same G-buffers over hand-made maps (lit, empty and NaN texels, back-facing
// and out-of-map pixels), under a sun and a spot; the radius growing with the light's size for every technique that
// takes it (split techniques: measured on split 0); the text form.
#include "host/pipeline/map_size.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "host/pipeline/renderer.h"
#include "host/scene/procedural.h"
#include "host/techniques/moment_map.h"
#include "host/techniques/technique.h"
#include "host/views/light_fit.h"
#include "host/views/views.h"
#include "tests/support/cl_test.h"
#include "tools/selftest/reference/analytic_scenes.h"

namespace penumbra {
namespace map_size_test {

constexpr double kBinsPerOctave = 8.0;  // FIT_SIZE_BINS_PER_OCTAVE

class MapSize : public test::ClTest {};

struct Grid {
  int width, height;
  std::vector<cl_float4> position, normal;
};

// A width x height G-buffer on the ground y = 0 whose x spacing grows across it (x = 0.02 * u^1.5, the shorter step
// throughout), z spacing 0.5,
// with background, NaN and far-outside pixels poisoned in.
Grid groundGrid(int width, int height) {
  Grid g{width, height, {}, {}};
  for (int v = 0; v < height; ++v)
    for (int u = 0; u < width; ++u) {
      g.position.push_back({{0.02f * std::pow(static_cast<float>(u), 1.5f), 0.0f, 0.5f * v, 1.0f}});
      g.normal.push_back({{0.0f, 1.0f, 0.0f, 1.0f}});
    }
  g.position[3].s[3] = 0.0f;                                             // background
  g.position[width + 5].s[0] = std::numeric_limits<float>::quiet_NaN();  // NaN
  g.position[2 * width + 7].s[0] = 1e6f;                                 // outside the map
  return g;
}

GBuffer upload(Context& ctx, const Grid& grid) {
  GBuffer g;
  g.width = grid.width, g.height = grid.height;
  g.position = Buffer<cl_float4>(ctx, std::span<const cl_float4>(grid.position));
  g.normal = Buffer<cl_float4>(ctx, std::span<const cl_float4>(grid.normal));
  return g;
}

glm::vec3 project(const LightView& lv, const cl_float4& p) {  // lv_project on the host
  const glm::vec4 world(p.s[0], p.s[1], p.s[2], 1.0f);
  const glm::vec4 clip = lv.raster.projection * lv.raster.view * world;
  return {(clip.x / clip.w * 0.5f + 0.5f) * lv.gpu.width, (clip.y / clip.w * 0.5f + 0.5f) * lv.gpu.height,
          -(lv.raster.view * world).z};
}

// The measure on the host: per pixel inside the map, the shorter of the steps to the +1 (else -1) neighbours in x
// and y that are surfaces (all on the one plane here), in texels; the bins of log2(width / step); the quantile's
// upper bin edge. `stride`: only the pixels on that grid are measured (fitSampleStride).
double referenceNeed(const Grid& g, const LightView& lv, double quantile, int stride = 1) {
  auto usable = [&](int i) {
    const cl_float4& p = g.position[i];
    if (p.s[3] == 0.0f || !std::isfinite(p.s[0])) return false;
    const glm::vec3 t = project(lv, p);
    return t.z > 0.0f && t.x >= 0.0f && t.y >= 0.0f && t.x <= lv.gpu.width && t.y <= lv.gpu.height;
  };
  auto step = [&](int i, int j) -> float {  // texel distance to neighbour j, 0 when it is no surface
    const cl_float4& q = g.position[j];
    if (q.s[3] == 0.0f || !std::isfinite(q.s[0])) return 0.0f;
    const glm::vec3 d = project(lv, q) - project(lv, g.position[i]);
    return std::isfinite(d.x) && std::isfinite(d.y) ? glm::length(glm::vec2(d)) : 0.0f;
  };
  std::vector<double> bins(128, 0.0);
  double total = 0;
  for (int y = 0; y < g.height; y += stride)
    for (int x = 0; x < g.width; x += stride) {
      const int i = y * g.width + x;
      if (!usable(i)) continue;
      float lx = x + 1 < g.width ? step(i, i + 1) : 0.0f;
      if (lx == 0.0f && x > 0) lx = step(i, i - 1);
      float ly = y + 1 < g.height ? step(i, i + g.width) : 0.0f;
      if (ly == 0.0f && y > 0) ly = step(i, i - g.width);
      const float s = lx > 0.0f && ly > 0.0f ? std::min(lx, ly) : std::max(lx, ly);
      if (!(s > 0.0f)) continue;
      const int bin = static_cast<int>(std::floor(std::log2(lv.gpu.width / s) * kBinsPerOctave));
      bins[std::clamp(bin, 0, 127)] += 1, total += 1;
    }
  double running = 0;
  size_t bin = 0;
  while (bin + 1 < bins.size() && (running += bins[bin]) < quantile * total) ++bin;
  return std::exp2((bin + 1) / kBinsPerOctave);
}

TEST_F(MapSize, QuantilesMatchTheHostReference) {
  const Grid grid = groundGrid(131, 37);  // not a multiple of the work-group
  const GBuffer g = upload(ctx(), grid);
  const Bounds bounds{{0, 0, 0}, {30, 0.5f, 18.5f}};
  for (const char* spec : {"dir:0.3,-1,0.2", "spot:15,12,9:15,0,9:120"}) {
    const LightView lv = fitLightView(parseLight(spec), bounds, 512);
    double last = 0;
    for (double q : {0.1, 0.5, 0.9, 1.0}) {
      const MapSizeNeed need = neededMapSize(ctx(), g, std::span<const LightViewGpu>(&lv.gpu, 1), q, 16, 1 << 16);
      EXPECT_EQ(need.needed, referenceNeed(grid, lv, q)) << spec << " q " << q;
      EXPECT_GE(need.needed, last) << spec << " q " << q;  // grows with the quantile
      EXPECT_GE(need.size, need.needed) << spec;           // the multiple of 128 at or above it
      EXPECT_LT(need.size, need.needed + kMapSizeStep) << spec;
      EXPECT_EQ(need.size % kMapSizeStep, 0) << spec;
      last = need.needed;
    }
    EXPECT_GT(last, 2 * referenceNeed(grid, lv, 0.1)) << spec << ": the spacing varies, so do the needs";
  }
}

// A frame of 4 x 8192 pixels or more is measured on a grid (stride 4 here, 15 at 1920x1080), each sample against its
// own neighbours: the same quantiles as the host's measure on that grid.
TEST_F(MapSize, LargeFramesAreMeasuredOnASampleGrid) {
  EXPECT_EQ(fitSampleStride(181 * 181), 1u);
  EXPECT_EQ(fitSampleStride(182 * 182), 2u);
  EXPECT_EQ(fitSampleStride(480 * 270), 3u);
  EXPECT_EQ(fitSampleStride(640 * 360), 5u);
  EXPECT_EQ(fitSampleStride(1920 * 1080), 15u);
  const Grid grid = groundGrid(601, 301);  // odd sizes: the last row and column are sampled
  ASSERT_EQ(fitSampleStride(601 * 301), 4u);
  const GBuffer g = upload(ctx(), grid);
  const Bounds bounds{{0, 0, 0}, {460, 0.5f, 201}};  // the whole grid
  const LightView lv = fitLightView(parseLight("dir:0.3,-1,0.2"), bounds, 512);
  for (double q : {0.1, 0.9}) {
    const MapSizeNeed need = neededMapSize(ctx(), g, std::span<const LightViewGpu>(&lv.gpu, 1), q, 16, 1 << 16);
    EXPECT_EQ(need.needed, referenceNeed(grid, lv, q, 4)) << q;
    EXPECT_LE(need.pixels, 151u * 76u);  // one pixel in sixteen
    EXPECT_GT(need.pixels, 151u * 76u / 2);
  }
}

TEST_F(MapSize, UniformGridNeedsItsOwnSpacingAndNoPixelsNeedNothing) {
  // 200 x 100 pixels 0.01 apart under a sun straight down: a texel per pixel is texelScale / 0.01 times the probe.
  Grid grid{200, 100, {}, {}};
  for (int v = 0; v < grid.height; ++v)
    for (int u = 0; u < grid.width; ++u) {
      grid.position.push_back({{0.01f * u, 0.0f, 0.01f * v, 1.0f}});
      grid.normal.push_back({{0.0f, 1.0f, 0.0f, 1.0f}});
    }
  const GBuffer g = upload(ctx(), grid);
  const Bounds bounds{{0, 0, 0}, {1.99f, 0.1f, 0.99f}};
  const LightView lv = fitLightView(parseLight("dir:0,-1,0.001"), bounds, 512);
  const double exact = 512.0 * lv.gpu.texelScale / 0.01;
  const MapSizeNeed need = neededMapSize(ctx(), g, std::span<const LightViewGpu>(&lv.gpu, 1), 0.9, 64, 8192);
  EXPECT_EQ(need.pixels, 200u * 100u);
  EXPECT_GE(need.needed, exact * (1 - 1e-4));
  EXPECT_LE(need.needed, exact * std::exp2(1 / kBinsPerOctave) * (1 + 1e-4));  // one bin above at most
  EXPECT_EQ(neededMapSize(ctx(), g, std::span<const LightViewGpu>(&lv.gpu, 1), 0.9, 64, 128).size, 128);  // capped

  Grid background = grid;
  for (cl_float4& p : background.position) p.s[3] = 0.0f;
  const MapSizeNeed none =
      neededMapSize(ctx(), upload(ctx(), background), std::span<const LightViewGpu>(&lv.gpu, 1), 0.9, 64, 8192);
  EXPECT_EQ(none.pixels, 0u);
  EXPECT_EQ(none.size, 64);
  Grid one{1, 1, {grid.position[0]}, {grid.normal[0]}};  // no neighbour, nothing measured
  EXPECT_EQ(neededMapSize(ctx(), upload(ctx(), one), std::span<const LightViewGpu>(&lv.gpu, 1), 0.9, 64, 8192).pixels,
            0u);
  EXPECT_THROW(neededMapSize(ctx(), g, std::span<const LightViewGpu>(&lv.gpu, 1), 0.0, 64, 8192),
               std::invalid_argument);
  EXPECT_THROW(neededMapSize(ctx(), g, std::span<const LightViewGpu>(&lv.gpu, 1), 0.9, 256, 128),
               std::invalid_argument);
  EXPECT_THROW(neededMapSize(ctx(), g, {}, 0.9, 64, 128), std::invalid_argument);
}

// The value an auto parameter took in a render, from its header's "auto N (...)" under `key`.
int chosenAuto(const RenderResult& r, const std::string& key) {
  const std::string& text = r.image.attributes().at(key);
  EXPECT_EQ(text.rfind("auto ", 0), 0u) << text;
  return std::stoi(text.substr(5));
}
int chosenSize(const RenderResult& r) { return chosenAuto(r, "penumbra:map-size"); }

TEST_F(MapSize, TheRendererSizesMapsToTheFrameForSpotAndPointLights) {
  const Scene scene = test::squareOverPlane();
  const TechniqueInfo& sm = findTechnique("sm");
  Params params(sm.params);
  params.set("map-size", "auto");
  params.set("map-size-max", "8192");
  for (const char* spec : {"spot:0,4,0:0,0,0:120", "point:0.3,3,0.2"}) {
    Camera camera = test::topDown();
    std::vector<int> sizes;
    for (int width : {120, 480}) {
      camera.width = width, camera.height = width * 3 / 4;
      Renderer renderer(ctx(), scene);
      const RenderResult r = renderer.render(camera, parseLight(spec), sm, params);
      sizes.push_back(chosenSize(r));
      // The technique drew the map at that size (a point light's faces: each of them).
      EXPECT_NE(r.image.attributes().at("penumbra:light-fit").find(fmt::format("{0}x{0}", sizes.back())),
                std::string::npos)
          << spec << ": " << r.image.attributes().at("penumbra:light-fit");
      EXPECT_EQ(r.image.attributes().at("penumbra:parameters").find("map-size=auto"), 0u);
    }
    EXPECT_GE(sizes[1], 2 * sizes[0]) << spec << ": four times the pixels across need larger maps";
    EXPECT_GE(sizes[0], 256) << spec;
  }
}

// The default: auto from 256 to 4096 texels, for every technique with one uniform map, its penumbra need 6 texels
// across a half-width (sm and pcf, which trace no wider penumbra than a few texels: 3; pcss 9; vssm 24) at the
// narrowest tenth of the shadowed pixels (the fifth for the techniques that blur their moments widely: vsm, evsm4, msm,
// savsm, lvsm), its cap 16 (sm and pcf: 4) and its caster need 2 texels across the thinnest features. The split
// techniques size every split as one map of the whole view, pssm with sm's and pcf's penumbra need, psvsm with vsm's,
// at most 2048 (the fixed size they had); jittered keeps 2048.
TEST(MapSizeDefaults, AutoFromThePixelsThePenumbraeAndTheCasters) {
  for (const char* name : {"sm", "pcf", "pcss", "vsm", "evsm2", "evsm4", "esm", "msm", "savsm", "vssm", "lvsm"}) {
    const Params params(findTechnique(name).params);
    const bool shortPenumbra = std::string(name) == "sm" || std::string(name) == "pcf";
    EXPECT_TRUE(params.isAuto("map-size")) << name;
    EXPECT_EQ(params.getInt("map-size-min"), 256) << name;
    EXPECT_EQ(params.getInt("map-size-max"), 4096) << name;
    const double penumbra = shortPenumbra                 ? 3.0
                            : std::string(name) == "vssm" ? 24.0
                            : std::string(name) == "pcss" ? 9.0
                                                          : 6.0;
    EXPECT_EQ(params.get("map-size-penumbra"), penumbra) << name;
    const std::set<std::string> blurred = {"vsm", "evsm4", "msm", "savsm", "lvsm"};
    EXPECT_EQ(params.get("map-size-penumbra-quantile"), blurred.count(name) ? 0.2 : 0.1) << name;
    EXPECT_EQ(params.get("map-size-penumbra-max"), shortPenumbra ? 4.0 : 16.0) << name;
    EXPECT_EQ(params.get("map-size-detail"), 2.0) << name;
  }
  for (const char* name : {"pssm", "psvsm"}) {
    const Params params(findTechnique(name).params);
    const bool pssm = std::string(name) == "pssm";
    EXPECT_TRUE(params.isAuto("map-size")) << name;
    EXPECT_EQ(params.getInt("map-size-min"), 256) << name;
    EXPECT_EQ(params.getInt("map-size-max"), 2048) << name;
    EXPECT_EQ(params.get("map-size-penumbra"), pssm ? 3.0 : 6.0) << name;
    EXPECT_EQ(params.get("map-size-penumbra-quantile"), pssm ? 0.1 : 0.2) << name;
    EXPECT_EQ(params.get("map-size-penumbra-max"), pssm ? 4.0 : 16.0) << name;
    EXPECT_EQ(params.get("map-size-detail"), 2.0) << name;
  }
  const Params jittered(findTechnique("jittered").params);
  EXPECT_FALSE(jittered.isAuto("map-size"));
  EXPECT_EQ(jittered.getInt("map-size"), 2048);
  EXPECT_FALSE(jittered.has("map-size-penumbra"));
}

// The needs a render records under "penumbra:map-size": "auto N (pixels: ...; penumbrae: ... need P; casters: ... need
// C)"; -1 for a need that is not there.
double recordedNeed(const RenderResult& r, const std::string& what) {
  const std::string& text = r.image.attributes().at("penumbra:map-size");
  const size_t at = text.find(what + ": ");
  if (at == std::string::npos) return -1.0;
  const size_t need = text.find(" need ", at);
  EXPECT_NE(need, std::string::npos) << text;
  return std::stod(text.substr(need + 6));
}

// The cap a render recorded on the pixels' need ("... caps the pixels' need at C"); -1 without one.
double recordedCap(const RenderResult& r) {
  const std::string& text = r.image.attributes().at("penumbra:map-size");
  const std::string key = "caps the pixels' need at ";
  const size_t at = text.find(key);
  return at == std::string::npos ? -1.0 : std::stod(text.substr(at + key.size()));
}

// The largest size at which a technique's kernel reach holds the median penumbra ("... holds that median up to S"), -1
// without one.
double recordedReach(const RenderResult& r) {
  const std::string& text = r.image.attributes().at("penumbra:map-size");
  const std::string key = "holds that median up to ";
  const size_t at = text.find(key);
  return at == std::string::npos ? -1.0 : std::stod(text.substr(at + key.size()));
}

// The size the recorded needs give: the pixels' (capped), the penumbrae's and the casters', the largest, at most where
// the technique's kernels hold the median penumbra.
int sizeFromNeeds(const RenderResult& r, int minSize, int maxSize) {
  const double cap = recordedCap(r), pixels = recordedNeed(r, "pixels"), reach = recordedReach(r);
  const double wanted =
      std::max({cap > 0.0 ? std::min(pixels, cap) : pixels, recordedNeed(r, "penumbrae"), recordedNeed(r, "casters")});
  return roundedMapSize(reach > 0.0 ? std::min(wanted, reach) : wanted, minSize, maxSize);
}

// Area lights: the smaller the light, the narrower the penumbrae and the larger the map, up to what the probe measured
// (a half-width of 9 texels for pcss, 3 for sm); a point light (no penumbra) and map-size-penumbra 0 leave the pixels'
// need.
TEST_F(MapSize, NarrowPenumbraeNeedLargerMaps) {
  const Scene scene = test::squareOverPlane();
  Camera camera = test::topDown();
  camera.width = 120, camera.height = 90;  // the pixels alone need a small map
  for (const char* name : {"pcss", "sm"}) {
    const TechniqueInfo& info = findTechnique(name);
    Params params(info.params);
    params.set("map-size-max", "8192");
    std::vector<int> sizes;
    for (const char* spec : {"spot:0,4,0:0,0,0:120:0.4", "spot:0,4,0:0,0,0:120:0.1", "spot:0,4,0:0,0,0:120:0.025"}) {
      Renderer renderer(ctx(), scene);
      const RenderResult r = renderer.render(camera, parseLight(spec), info, params);
      sizes.push_back(chosenSize(r));
      const double penumbra = recordedNeed(r, "penumbrae"), pixels = recordedNeed(r, "pixels");
      ASSERT_GT(penumbra, 0.0) << name << " " << spec << ": " << r.image.attributes().at("penumbra:map-size");
      EXPECT_GT(pixels, 0.0) << name << " " << spec;
      EXPECT_EQ(sizes.back(), sizeFromNeeds(r, 256, 8192)) << name << " " << spec;
    }
    EXPECT_GT(sizes[1], sizes[0]) << name;
    EXPECT_GT(sizes[2], 2 * sizes[1]) << name << ": a quarter of the light, a quarter of the penumbra";
    // The same light without the penumbra's need, and a light without a penumbra.
    params.set("map-size-penumbra", "0");
    Renderer renderer(ctx(), scene);
    const RenderResult off = renderer.render(camera, parseLight("spot:0,4,0:0,0,0:120:0.025"), info, params);
    EXPECT_EQ(recordedNeed(off, "penumbrae"), -1.0) << name;
    EXPECT_LT(chosenSize(off), sizes[2]) << name;
    params.set("map-size-penumbra", "6");
    const RenderResult hard = renderer.render(camera, parseLight("spot:0,4,0:0,0,0:120"), info, params);
    EXPECT_EQ(recordedNeed(hard, "penumbrae"), -1.0) << name;
    EXPECT_EQ(chosenSize(hard), chosenSize(off)) << name;
  }
  // sm asks a third of the texels across a penumbra that pcss does (3 against 9), a filter at 6 twice sm's.
  Params pcss(findTechnique("pcss").params), sm(findTechnique("sm").params);
  Renderer renderer(ctx(), scene);
  const Light light = parseLight("spot:0,4,0:0,0,0:120:0.1");
  const double filterNeed = recordedNeed(renderer.render(camera, light, findTechnique("pcss"), pcss), "penumbrae");
  const double hardNeed = recordedNeed(renderer.render(camera, light, findTechnique("sm"), sm), "penumbrae");
  EXPECT_NEAR(hardNeed, filterNeed / 3, 0.5);  // the header records whole texels
  pcss.set("map-size-penumbra", "6");
  const double sixNeed = recordedNeed(renderer.render(camera, light, findTechnique("pcss"), pcss), "penumbrae");
  EXPECT_NEAR(hardNeed, sixNeed / 2, 1e-6 * sixNeed);
}

// Wide penumbrae cap the pixels' need: a large light over the square, seen by a large frame, gets a smaller map than
// its pixels ask for (the median half-width spans 16 texels, 4 for sm), and the frame's size is that cap or what the
// narrow end of its penumbrae needs; --map-size-penumbra-max 0 gives the pixels' need.
TEST_F(MapSize, WidePenumbraeCapThePixelsNeed) {
  const Scene scene = test::squareOverPlane();
  Camera camera = test::topDown();
  camera.width = 800, camera.height = 600;
  const Light light = parseLight("spot:0,4,0:0,0,0:120:1.5");
  for (const char* name : {"pcss", "sm"}) {
    const TechniqueInfo& info = findTechnique(name);
    Params params(info.params);
    params.set("map-size-max", "8192");
    // pcss's kernels would hold these wide penumbrae only at smaller sizes (KernelsHoldTheMedianPenumbra): not here.
    if (info.hasParam("pcss-max-radius")) params.set("pcss-max-radius", "512");
    Renderer renderer(ctx(), scene);
    const RenderResult capped = renderer.render(camera, light, info, params);
    const double cap = recordedCap(capped), pixels = recordedNeed(capped, "pixels");
    ASSERT_GT(cap, 0.0) << name << ": " << capped.image.attributes().at("penumbra:map-size");
    EXPECT_LT(cap, pixels) << name << ": " << capped.image.attributes().at("penumbra:map-size");
    EXPECT_EQ(chosenSize(capped), sizeFromNeeds(capped, 256, 8192)) << name;
    params.set("map-size-penumbra-max", "0");
    const RenderResult uncapped = renderer.render(camera, light, info, params);
    EXPECT_EQ(recordedCap(uncapped), -1.0) << name;
    EXPECT_EQ(chosenSize(uncapped), roundedMapSize(std::max(pixels, recordedNeed(uncapped, "penumbrae")), 256, 8192))
        << name;
    EXPECT_LT(chosenSize(capped), chosenSize(uncapped)) << name;
  }
}

// vssm and pcss clamp their kernels at --vssm-max-radius and --pcss-max-radius texels: under a large light whose median
// penumbra would span more, the size is held at the largest multiple of 128 where it spans no more, below what the
// needs ask for, and it follows the parameter.
TEST_F(MapSize, KernelsHoldTheMedianPenumbra) {
  const Scene scene = test::squareOverPlane();
  Camera camera = test::topDown();
  camera.width = 400, camera.height = 300;
  const Light light = parseLight("spot:0,4,0:0,0,0:120:0.4");
  for (const char* name : {"vssm", "pcss"}) {
    const TechniqueInfo& info = findTechnique(name);
    const std::string reachParam = std::string(name) + "-max-radius";
    Params params(info.params);
    params.set("map-size-max", "8192");
    Renderer renderer(ctx(), scene);
    params.set(reachParam, "512");  // a reach no size comes near: the needs alone
    const RenderResult free = renderer.render(camera, light, info, params);
    EXPECT_EQ(recordedReach(free), -1.0) << name << ": " << free.image.attributes().at("penumbra:map-size");
    EXPECT_EQ(chosenSize(free), sizeFromNeeds(free, 256, 8192)) << name;
    params.set(reachParam, "16");
    const RenderResult capped = renderer.render(camera, light, info, params);
    const std::string& text = capped.image.attributes().at("penumbra:map-size");
    const double reach = recordedReach(capped);
    ASSERT_GT(reach, 0.0) << name << ": " << text;
    EXPECT_EQ(chosenSize(capped), reach) << name << ": " << text;
    EXPECT_LT(chosenSize(capped), sizeFromNeeds(free, 256, 8192)) << name << ": " << text;  // below the needs
    params.set(reachParam, "32");  // twice the reach, twice the size or one step of 128 more
    const RenderResult wider = renderer.render(camera, light, info, params);
    EXPECT_GE(recordedReach(wider), 2.0 * reach) << name << ": " << wider.image.attributes().at("penumbra:map-size");
    EXPECT_LE(recordedReach(wider), 2.0 * reach + 128.0) << name;
  }
}

// Thin casters: the poles (0.1 wide) under a hard spot light are a texel or two wide in the probe, so the casters'
// need asks for twice the probe's size per texel they lack; without it, the pixels' need alone.
TEST_F(MapSize, ThinCastersNeedLargerMaps) {
  const Scene scene = makeProcedural("poles");
  Camera camera = scene.cameras.front();
  camera.width = 96, camera.height = 54;
  const TechniqueInfo& sm = findTechnique("sm");
  Params params(sm.params);
  Light light = scene.lights.front();  // its own light without its size: no penumbra need
  light.radius = 0.0f, light.angularRadiusDeg = 0.0f;
  Renderer renderer(ctx(), scene);
  const RenderResult r = renderer.render(camera, light, sm, params);
  const double casters = recordedNeed(r, "casters");
  EXPECT_GE(casters, kMapProbeSize) << r.image.attributes().at("penumbra:map-size");
  EXPECT_GT(casters, recordedNeed(r, "pixels")) << r.image.attributes().at("penumbra:map-size");
  EXPECT_EQ(chosenSize(r), roundedMapSize(casters, 256, 4096));
  params.set("map-size-detail", "0");
  const RenderResult off = renderer.render(camera, light, sm, params);
  EXPECT_EQ(recordedNeed(off, "casters"), -1.0);
  EXPECT_LT(chosenSize(off), chosenSize(r));
}

TEST_F(MapSize, AutoIsATextValueThatJitteredRefuses) {
  const TechniqueInfo& sm = findTechnique("sm");
  Params params(sm.params);
  params.set("map-size", "auto");
  EXPECT_EQ(params.get("map-size"), 0.0);
  EXPECT_NE(params.describe().find("map-size=auto "), std::string::npos);
  EXPECT_THROW(params.set("map-size", "0"), std::invalid_argument);  // 0 is auto's, not a size
  for (const char* name : {"jittered", "fvsm"}) {
    const TechniqueInfo& info = findTechnique(name);
    Params fixed(info.params);
    EXPECT_THROW(fixed.set("map-size", "auto"), std::invalid_argument) << name;
    EXPECT_FALSE(info.hasParam("map-size-quantile")) << name;
  }
}

// Penumbra half-width a pixel's receiver and the map's texel give (lv_penumbra_texels), or with `distance` the
// occluder's distance in front of the receiver; -1 where not counted.
double referenceHalfWidth(const LightView& lv, const std::vector<float>& map, const cl_float4& p, const cl_float4& n,
                          bool distance = false) {
  if (p.s[3] == 0.0f || !std::isfinite(p.s[0])) return -1;
  const glm::vec3 world(p.s[0], p.s[1], p.s[2]);
  const glm::vec3 toLight =
      lv.gpu.kind == LIGHT_KIND_SPOT
          ? glm::normalize(glm::vec3(lv.gpu.position.s[0], lv.gpu.position.s[1], lv.gpu.position.s[2]) - world)
          : -glm::vec3(lv.gpu.axis.s[0], lv.gpu.axis.s[1], lv.gpu.axis.s[2]);
  if (!(glm::dot(glm::vec3(n.s[0], n.s[1], n.s[2]), toLight) > 0.0f)) return -1;
  const glm::vec3 t = project(lv, p);
  const int x = static_cast<int>(std::floor(t.x)), y = static_cast<int>(std::floor(t.y));
  if (!(t.z > 0.0f) || x < 0 || y < 0 || x >= static_cast<int>(lv.gpu.width) || y >= static_cast<int>(lv.gpu.height))
    return -1;
  const double occluder = map[static_cast<size_t>(y) * lv.gpu.width + x], receiver = t.z;
  if (!(occluder < receiver)) return -1;
  if (distance) return receiver - occluder;
  const double world_width = lv.gpu.kind == LIGHT_KIND_SPOT
                                 ? lv.gpu.lightSize * (receiver - occluder) / std::max<double>(occluder, lv.gpu.zNear)
                                 : lv.gpu.lightSize * (receiver - occluder);
  const double texel = lv.gpu.kind == LIGHT_KIND_SPOT ? lv.gpu.texelScale * receiver : lv.gpu.texelScale;
  return world_width / texel;
}

// The quantile of the counted pixels' half-widths, sorted (the device bins them: within a bin of it).
double referenceQuantile(std::vector<double> widths, double quantile) {
  std::sort(widths.begin(), widths.end());
  const auto k = static_cast<size_t>(std::ceil(quantile * static_cast<double>(widths.size())));
  return widths[std::max<size_t>(k, 1) - 1];
}

class PenumbraWidthTest : public test::ClTest {};

// Occluders in front of the ground at a distance that varies over `lv`'s map; every 5th texel empty, every 7th NaN, a
// band of texels behind the receivers (lit).
std::vector<float> syntheticOccluders(const LightView& lv) {
  const size_t texels = static_cast<size_t>(lv.gpu.width) * static_cast<size_t>(lv.gpu.height);
  std::vector<float> map(texels);
  for (size_t i = 0; i < texels; ++i) {
    const float x = static_cast<float>(i % lv.gpu.width) / lv.gpu.width;
    const float y = static_cast<float>(i / lv.gpu.width) / lv.gpu.height;
    map[i] = i % 5 == 0   ? INFINITY
             : i % 7 == 0 ? std::numeric_limits<float>::quiet_NaN()
                          : lv.gpu.zNear + (lv.gpu.zFar - lv.gpu.zNear) * (0.1f + 0.8f * x * y);
  }
  return map;
}

TEST_F(PenumbraWidthTest, QuantilesMatchTheHostReferenceUnderASunAndASpot) {
  Grid grid = groundGrid(131, 37);                                // not a multiple of the work-group
  grid.normal[4 * grid.width + 9] = {{0.0f, -1.0f, 0.0f, 1.0f}};  // back-facing: not counted
  const GBuffer g = upload(ctx(), grid);
  const Bounds bounds{{0, 0, 0}, {30, 0.5f, 18.5f}};
  for (const char* spec : {"dir:0.3,-1,0.2", "spot:15,12,9:15,0,9:120"}) {
    LightView lv = fitLightView(parseLight(spec), bounds, 256);
    lv.gpu.lightSize = lv.gpu.kind == LIGHT_KIND_SPOT ? 1.0f : 0.02f;  // a spot of radius 1, a sun of tan 0.02
    const Buffer<LightViewGpu> view(ctx(), std::span<const LightViewGpu>(&lv.gpu, 1), CL_MEM_READ_ONLY);
    const std::vector<float> map = syntheticOccluders(lv);
    const Buffer<float> depth(ctx(), std::span<const float>(map));
    std::vector<double> widths;
    for (size_t i = 0; i < grid.position.size(); ++i) {
      const double h = referenceHalfWidth(lv, map, grid.position[i], grid.normal[i]);
      if (h >= 0) widths.push_back(h);
    }
    ASSERT_GT(widths.size(), 1000u) << spec;
    ASSERT_LT(widths.size(), grid.position.size() * 9 / 10) << spec << ": some lit, empty, NaN and skipped";
    const double bin = std::exp2(1.0 / kBinsPerOctave);
    double last = 0;
    for (double q : {0.05, 0.25, 0.5, 0.9}) {
      const PenumbraWidth w = measurePenumbraWidth(ctx(), g, depth, view, {0, 0, 0}, q);
      EXPECT_EQ(w.pixels, widths.size()) << spec;
      const double want = referenceQuantile(widths, q);
      EXPECT_GE(w.halfWidth, want / bin) << spec << " q " << q;  // the bin's centre, so within a bin either way
      EXPECT_LE(w.halfWidth, want * bin) << spec << " q " << q;
      EXPECT_GE(w.halfWidth, last) << spec << " q " << q;
      last = w.halfWidth;
    }
    EXPECT_GT(last, 2 * referenceQuantile(widths, 0.05)) << spec << ": the distances vary, so do the widths";
    // The occluders' distances (savsm's auto distance), in units of 0.37 world units.
    std::vector<double> distances;
    for (size_t i = 0; i < grid.position.size(); ++i) {
      const double d = referenceHalfWidth(lv, map, grid.position[i], grid.normal[i], true);
      if (d >= 0) distances.push_back(d);
    }
    for (double q : {0.1, 0.5}) {
      const OccluderDistance d = measureOccluderDistance(ctx(), g, depth, view, {0, 0, 0}, q, 0.37f);
      EXPECT_EQ(d.pixels, distances.size()) << spec;
      EXPECT_GE(d.distance, referenceQuantile(distances, q) / bin) << spec << " q " << q;
      EXPECT_LE(d.distance, referenceQuantile(distances, q) * bin) << spec << " q " << q;
    }
    EXPECT_THROW(measureOccluderDistance(ctx(), g, depth, view, {0, 0, 0}, 0.5, 0.0f), std::invalid_argument);
  }
}

// From 4 x 8192 pixels on, the penumbra histogram is measured on the same sample grid as the map size's need (stride
// 4 here): the host reference over those pixels, within a bin.
TEST_F(PenumbraWidthTest, LargeFramesAreMeasuredOnASampleGrid) {
  const Grid grid = groundGrid(601, 301);
  ASSERT_EQ(fitSampleStride(grid.position.size()), 4u);
  const GBuffer g = upload(ctx(), grid);
  LightView lv = fitLightView(parseLight("dir:0.3,-1,0.2"), Bounds{{0, 0, 0}, {460, 0.5f, 201}}, 256);
  lv.gpu.lightSize = 0.02f;
  const Buffer<LightViewGpu> view(ctx(), std::span<const LightViewGpu>(&lv.gpu, 1), CL_MEM_READ_ONLY);
  const std::vector<float> map = syntheticOccluders(lv);
  const Buffer<float> depth(ctx(), std::span<const float>(map));
  std::vector<double> widths;
  for (int y = 0; y < grid.height; y += 4)
    for (int x = 0; x < grid.width; x += 4) {
      const size_t i = static_cast<size_t>(y) * grid.width + x;
      const double h = referenceHalfWidth(lv, map, grid.position[i], grid.normal[i]);
      if (h >= 0) widths.push_back(h);
    }
  ASSERT_GT(widths.size(), 2000u);
  const double bin = std::exp2(1.0 / kBinsPerOctave);
  for (double q : {0.05, 0.5}) {
    const PenumbraWidth w = measurePenumbraWidth(ctx(), g, depth, view, {0, 0, 0}, q);
    EXPECT_EQ(w.pixels, widths.size()) << q;
    EXPECT_GE(w.halfWidth, referenceQuantile(widths, q) / bin) << q;
    EXPECT_LE(w.halfWidth, referenceQuantile(widths, q) * bin) << q;
  }
}

TEST_F(PenumbraWidthTest, LitEmptyAndOneByOneFramesMeasureNothing) {
  Grid grid = groundGrid(64, 16);
  const GBuffer g = upload(ctx(), grid);
  const LightView lv = fitLightView(parseLight("dir:0,-1,0.001"), {{0, 0, 0}, {30, 0.5f, 8}}, 64);
  const Buffer<LightViewGpu> view(ctx(), std::span<const LightViewGpu>(&lv.gpu, 1), CL_MEM_READ_ONLY);
  const Buffer<float> empty(ctx(), std::vector<float>(64 * 64, INFINITY));
  const PenumbraWidth none = measurePenumbraWidth(ctx(), g, empty, view, {1, 1, 1}, 0.5);
  EXPECT_EQ(none.pixels, 0u);
  EXPECT_EQ(none.halfWidth, 0.0);
  // An occluder touching its receivers: counted, at width 0.
  const Buffer<float> contact(ctx(), std::vector<float>(64 * 64, -1e-3f));
  const PenumbraWidth touching = measurePenumbraWidth(ctx(), g, contact, view, {0, 0, 0}, 0.5);
  EXPECT_GT(touching.pixels, 0u);
  EXPECT_EQ(touching.halfWidth, 0.0);
  Grid one{1, 1, {grid.position[0]}, {grid.normal[0]}};
  EXPECT_EQ(measurePenumbraWidth(ctx(), upload(ctx(), one), empty, view, {1, 1, 1}, 0.5).pixels, 0u);
  GBuffer nothing;
  EXPECT_EQ(measurePenumbraWidth(ctx(), nothing, empty, view, {1, 1, 1}, 0.5).pixels, 0u);
  EXPECT_THROW(measurePenumbraWidth(ctx(), g, empty, view, {1, 1, 1}, 0.0), std::invalid_argument);
  EXPECT_THROW(measurePenumbraWidth(ctx(), g, empty, view, {1, 1, 1}, 1.5), std::invalid_argument);
}

TEST_F(PenumbraWidthTest, TheRadiusGrowsWithTheLightsSizeUpToItsMaximum) {
  const Scene scene = test::squareOverPlane();
  Camera camera = test::topDown();
  const std::pair<const char*, std::string> cases[] = {
      {"vsm", "blur-radius"},   {"evsm4", "blur-radius"}, {"msm", "blur-radius"}, {"lvsm", "blur-radius"},
      {"psvsm", "blur-radius"}, {"pcf", "pcf-radius"},    {"pssm", "pcf-radius"}};
  for (const auto& [name, radius] : cases) {
    const TechniqueInfo& info = findTechnique(name);
    Params params(info.params);
    params.set(radius + "-max", "16");
    params.set("map-size", "2048");  // one size for every light: the radius in texels follows the penumbra alone
    EXPECT_TRUE(AutoRadius::from(params, radius).automatic) << name << ": the default";
    const auto chosen = [&](const char* light, const Params& p) {
      Renderer renderer(ctx(), scene);
      return chosenAuto(renderer.render(camera, parseLight(light), info, p), "penumbra:" + radius);
    };
    std::vector<int> radii;
    for (const char* spec : {"spot:0,4,0:0,0,0:90:0.0001", "spot:0,4,0:0,0,0:90:0.005", "spot:0,4,0:0,0,0:90:0.02"})
      radii.push_back(chosen(spec, params));
    EXPECT_EQ(radii[0], 0) << name << ": a point-like light needs no filter";
    EXPECT_GT(radii[1], 0) << name;
    EXPECT_GT(radii[2], radii[1]) << name << ": a larger light, wider penumbrae";
    EXPECT_LT(radii[2], 16) << name << ": the test's lights stay below the maximum";
    params.set(radius + "-max", "1");
    EXPECT_EQ(chosen("spot:0,4,0:0,0,0:90:0.4", params), 1) << name;
  }
}

TEST_F(PenumbraWidthTest, SavsmsAutoDistanceScalesWithTheScene) {
  // The box scene at 1 and at 10 times its size (camera, light and ground scale with it): the same frame, so the
  // measured distance scales by 10 (within a bin each) and the image stays the same.
  const TechniqueInfo& savsm = findTechnique("savsm");
  const Params params(savsm.params);
  std::vector<double> distances;
  std::vector<std::vector<float>> images;
  for (double size : {1.0, 10.0}) {
    const Scene scene = makeProcedural("box", {{"size", size}, {"ground", 10 * size}});
    Camera camera = scene.cameras.front();
    camera.width = 96, camera.height = 64;
    Renderer renderer(ctx(), scene);
    const RenderResult r = renderer.render(camera, scene.lights.front(), savsm, params);
    const std::string& text = r.image.attributes().at("penumbra:savsm-occluder-distance");
    ASSERT_EQ(text.rfind("auto ", 0), 0u) << text;
    distances.push_back(std::stod(text.substr(5)));
    images.push_back(r.image.require("visibility.Y").data);
  }
  ASSERT_GT(distances[0], 0.0);
  EXPECT_NEAR(distances[1] / distances[0], 10.0, 10.0 * (std::exp2(2.0 / kBinsPerOctave) - 1)) << "two bins at most";
  double worst = 0;
  for (size_t i = 0; i < images[0].size(); ++i) worst = std::max(worst, double(std::fabs(images[0][i] - images[1][i])));
  EXPECT_LT(worst, 0.05) << "a scene's units do not change its shadows";
}

TEST_F(PenumbraWidthTest, AutoIsTheRadiusDefaultOfEveryFixedKernel) {
  for (const char* name : {"vsm", "evsm2", "evsm4", "esm", "msm", "lvsm", "psvsm"}) {
    Params params(findTechnique(name).params);
    EXPECT_NE(params.describe().find("blur-radius=auto "), std::string::npos) << name;
  }
  Params params(findTechnique("vsm").params);
  params.set("blur-radius", "0");
  EXPECT_FALSE(AutoRadius::from(params, "blur-radius").automatic);
  EXPECT_EQ(AutoRadius::from(params, "blur-radius").radius, 0);  // 0 stays off, not auto
  EXPECT_EQ(momentBlurReach(MomentFilter::from(params, 2048)), 0.0f);
  params.set("blur-radius", "auto");
  const AutoRadius blur = MomentFilter::from(params, 2048).blur;
  EXPECT_TRUE(blur.automatic);
  EXPECT_EQ(blur.limit(), 16);  // the map's margin before it is measured
  // The Gaussian of the largest radius reaches 3 sigma: sigma^2 = r (r + 1) / 3.
  EXPECT_EQ(momentBlurReach(MomentFilter::from(params, 2048)), std::ceil(3.0f * std::sqrt(16.0f * 17.0f / 3.0f)));
  EXPECT_THROW(params.set("blur-radius", "-1"), std::invalid_argument);  // auto's value is not a radius
  // blur-radius-max auto: a 128th of the map's side, at least 16 (the same reach in the scene at every size).
  EXPECT_TRUE(params.isAuto("blur-radius-max"));
  for (const auto& [side, max] : {std::pair{256, 16}, {2048, 16}, {2176, 17}, {4096, 32}, {8192, 64}})
    EXPECT_EQ(MomentFilter::from(params, side).blur.limit(), max) << side;
  params.set("blur-radius-max", "16");
  EXPECT_EQ(MomentFilter::from(params, 4096).blur.limit(), 16);  // a number is kept at every size
  EXPECT_THROW(params.set("blur-radius-max", "-1"), std::invalid_argument);
  for (const char* name : {"esm", "evsm2"}) {  // a fixed 2 at every size
    const Params positive(findTechnique(name).params);
    EXPECT_EQ(positive.getInt("blur-radius-max"), 2) << name;
    EXPECT_EQ(MomentFilter::from(positive, 4096).blur.limit(), 2) << name;
  }
  for (const char* name : {"pcf", "pssm"}) {
    Params pcf(findTechnique(name).params);
    EXPECT_TRUE(AutoRadius::from(pcf, "pcf-radius").automatic) << name;
    EXPECT_EQ(pcf.getInt("pcf-radius-max"), 4) << name;
  }
  EXPECT_EQ(Params(findTechnique("pcf").params).getInt("pcf-adaptive"), 0);  // the penumbra's width, not the footprint
}

// Caster detail (kernels/fit.cl fit_detail_partial, through MapDetailMeter) against a C++ reference of the same
// definition: along every row and column, runs of texels entered by a step towards the light and left by a step away
// from it, each a depth jump of more than 8 texel widths at the nearer side; background and NaN infinitely deep.
std::vector<uint64_t> referenceDetail(const LightViewGpu& lv, const std::vector<float>& map, int size) {
  std::vector<uint64_t> bins(64, 0);
  const auto texel = [&](float d) { return lv.kind == LIGHT_KIND_SPOT ? lv.texelScale * d : lv.texelScale; };
  for (int line = 0; line < 2 * size; ++line) {
    const auto at = [&](int k) {
      const float d = line < size ? map[size_t(line) * size + k] : map[size_t(k) * size + (line - size)];
      return std::isnan(d) ? INFINITY : d;
    };
    int start = -1;
    float prev = at(0);
    for (int k = 1; k < size; ++k) {
      const float d = at(k), jump = 8.0f * texel(std::min(d, prev));
      if (d < prev - jump) {
        start = k;
      } else if (start >= 0 && d > prev + jump) {
        ++bins[std::min(k - start, 64) - 1];
        start = -1;
      }
      prev = d;
    }
  }
  return bins;
}

// A receiver plane at depth ~10 (a gentle slope: no jumps) with background in one corner; bars at depth 5 of widths
// 1, 2, 3, 5, 8, 13 and 70 along the rows (a pseudo-random layout), a bar at depth 2 nested on one at 5, a ramp steeper
// than the jump threshold (steps one way only), every 97th texel NaN.
std::vector<float> detailMap(int size) {
  std::vector<float> map(size_t(size) * size);
  const int widths[] = {1, 2, 3, 5, 8, 13, 70};
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      float d = 10.0f + 0.001f * float(x + y);
      if (x < size / 8 && y < size / 8) d = INFINITY;
      const int w = widths[(y * 7 + 3) % 7], at = (y * 37) % std::max(size - w, 1);
      if (x >= at && x < at + w) d = 5.0f;
      if (y % 11 == 0 && x >= size / 2 && x < size / 2 + 12) d = x < size / 2 + 4 ? 5.0f : 2.0f;
      if (y % 13 == 0 && x >= size / 3 && x < size / 3 + 6) d = 9.0f - 3.0f * float(x - size / 3);
      if ((size_t(y) * size + x) % 97 == 0) d = std::numeric_limits<float>::quiet_NaN();
      map[size_t(y) * size + x] = d;
    }
  return map;
}

TEST_F(MapSize, CasterDetailMatchesTheHostReference) {
  const Bounds bounds{{0, 0, 0}, {30, 0.5f, 18.5f}};
  for (const char* spec : {"dir:0.3,-1,0.2", "spot:15,12,9:15,0,9:120"})
    for (int size : {1, 3, 131, 300}) {
      const LightView lv = fitLightView(parseLight(spec), bounds, size);
      const Buffer<LightViewGpu> view(ctx(), std::span<const LightViewGpu>(&lv.gpu, 1), CL_MEM_READ_ONLY);
      const std::vector<float> map = detailMap(size);
      const Buffer<float> depth(ctx(), std::span<const float>(map));
      MapDetailMeter meter;
      meter.add(ctx(), GBuffer{}, depth, size, view, {0, 0, 0}, false);
      const std::vector<uint64_t> want = referenceDetail(lv.gpu, map, size);
      uint64_t total = 0;
      for (uint64_t b : want) total += b;
      EXPECT_EQ(meter.features(), total) << spec << " " << size;
      if (size < 100) continue;
      EXPECT_GT(total, uint64_t(size)) << spec << ": the bars are counted";
      for (double q : {0.05, 0.25, 0.5, 0.9, 1.0}) {
        uint64_t running = 0;
        size_t bin = 0;
        while (bin + 1 < want.size() && double(running += want[bin]) < q * double(total)) ++bin;
        EXPECT_EQ(meter.featureWidth(q), double(bin + 1)) << spec << " " << size << " q " << q;
      }
      // A second map adds to the counts (a point light's faces).
      meter.add(ctx(), GBuffer{}, depth, size, view, {0, 0, 0}, false);
      EXPECT_EQ(meter.features(), 2 * total) << spec << " " << size;
    }
  // Nothing drawn: no feature, width 0.
  const LightView lv = fitLightView(parseLight("dir:0.3,-1,0.2"), bounds, 64);
  const Buffer<LightViewGpu> view(ctx(), std::span<const LightViewGpu>(&lv.gpu, 1), CL_MEM_READ_ONLY);
  const std::vector<float> empty(64 * 64, INFINITY);
  const Buffer<float> depth(ctx(), std::span<const float>(empty));
  MapDetailMeter meter;
  meter.add(ctx(), GBuffer{}, depth, 64, view, {0, 0, 0}, false);
  EXPECT_EQ(meter.features(), 0u);
  EXPECT_EQ(meter.featureWidth(0.5), 0.0);
}

}  // namespace map_size_test
}  // namespace penumbra
