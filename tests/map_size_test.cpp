// --map-size auto (host/pipeline/map_size.h, host/views/light_fit.h neededMapSize, kernels/fit.cl
// fit_size_partial): the device histogram's quantiles against a plain C++ reference of the same measure on a
// G-buffer with a spacing that varies across it, background, NaN and out-of-map pixels among them; the analytic
// need of a uniform grid; the renderer choosing larger maps for larger frames, for spot and point lights; the
// parameter's text form, and the techniques that refuse it.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "host/pipeline/renderer.h"
#include "host/techniques/technique.h"
#include "host/views/light_fit.h"
#include "host/views/views.h"
#include "tests/support/analytic_scenes.h"
#include "tests/support/cl_test.h"

namespace penumbra {
namespace {

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
// upper bin edge.
double referenceNeed(const Grid& g, const LightView& lv, double quantile) {
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
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
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
      EXPECT_GE(need.size, need.needed) << spec;           // the power of two above it
      EXPECT_LT(need.size, 2 * need.needed) << spec;
      last = need.needed;
    }
    EXPECT_GT(last, 2 * referenceNeed(grid, lv, 0.1)) << spec << ": the spacing varies, so do the needs";
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

// The size a render chose, from its header.
int chosenSize(const RenderResult& r) {
  const std::string& text = r.image.attributes().at("penumbra:map-size");
  EXPECT_EQ(text.rfind("auto ", 0), 0u) << text;
  return std::stoi(text.substr(5));
}

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

TEST_F(MapSize, AutoIsATextValueThatSplitAndJitteredTechniquesRefuse) {
  const TechniqueInfo& sm = findTechnique("sm");
  Params params(sm.params);
  params.set("map-size", "auto");
  EXPECT_EQ(params.get("map-size"), 0.0);
  EXPECT_NE(params.describe().find("map-size=auto "), std::string::npos);
  EXPECT_THROW(params.set("map-size", "0"), std::invalid_argument);  // 0 is auto's, not a size
  for (const char* name : {"pssm", "psvsm", "jittered"}) {
    const TechniqueInfo& info = findTechnique(name);
    Params fixed(info.params);
    EXPECT_THROW(fixed.set("map-size", "auto"), std::invalid_argument) << name;
    EXPECT_FALSE(info.hasParam("map-size-quantile")) << name;
  }
}

}  // namespace
}  // namespace penumbra
