// Techniques on the caller's own light map and G-buffer (host/pipeline/caller_shade.h, pn_shade's core): given the map
// a Renderer's technique draws and the Renderer's G-buffer, every technique that can shade from one map gives the
// Renderer's visibility; a depth buffer's conventions (OpenGL, reversed Z) and layouts (offset, row pitch, rows from
// the top) give what the packed linear map gives; a G-buffer from a depth buffer, and normals from positions, come
// close to the Renderer's; inputs that cannot work are refused by name before any work.
#include "host/pipeline/caller_shade.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "host/pipeline/renderer.h"
#include "host/scene/load.h"
#include "host/techniques/registry.h"
#include "host/views/raster_scene.h"
#include "host/views/views.h"
#include "raster/rasterizer.h"
#include "tests/support/cl_test.h"

namespace penumbra {
namespace caller_shade_test {

constexpr int kMapSize = 512;
// Visibility from the caller's map against the Renderer's, with the fit's own depth range: the same kernels on the
// same texels, but the light's position, axis and texel size are recovered from the caller's matrices, one float
// round-off from the fit's (measured: at most 3.5e-5, vssm; sm 0).
constexpr float kSameMapTolerance = 1e-4f;

struct Staged {
  Scene scene;
  Camera camera;
};

Staged staircase() {
  Staged s{loadScene("builtin:staircase"), {}};
  s.camera = s.scene.cameras.at(0);
  s.camera.width = 200, s.camera.height = 120;
  return s;
}

// An area spot light above the scene and a sun with a disk.
std::vector<Light> areaLights(const Scene& scene) {
  const Bounds b = scene.bounds();
  const glm::vec3 c = b.center();
  Light spot;
  spot.type = LightType::Spot;
  spot.position = c + glm::vec3(0.6f, 1.6f, 0.4f) * b.radius();
  spot.target = c;
  spot.fovDeg = 80.0f;
  spot.radius = 0.06f * b.radius();
  Light sun = parseLight("dir:0.4,-1,0.3:2");
  return {spot, sun};
}

// What the Renderer draws for a technique with --fit scene: the view of the whole scene, whatever the filter's reach.
struct DrawnMap {
  LightView view;
  RasterTargets targets;
};

// castersOnly: without what can shadow no receiver (RasterView::casterLight), as the renderer draws the maps of the
// techniques that only compare depths (ShadowMap::castersOnly).
DrawnMap drawMap(Rasterizer& raster, const Scene& scene, const Light& light, bool castersOnly = false) {
  DrawnMap m{fitLightView(light, scene.bounds(), kMapSize), {}};
  if (castersOnly) m.view.raster.casterLight = rasterLightOf(light);
  raster.draw(m.view.raster, m.targets);
  return m;
}

// The techniques whose renderer draws their map of casters only (ShadowMap::castersOnly).
bool drawsCastersOnly(const std::string& technique) {
  return technique == "sm" || technique == "pcf" || technique == "pcss";
}

Buffer<float> floats(Context& ctx, const Buffer<cl_float4>& b) {
  return Buffer<float>::over(b.get(), b.size() * 4, ctx.context()());
}

CallerLightMap linearMap(Context& ctx, const DrawnMap& m) {
  CallerLightMap map;
  map.depth.buffer = Buffer<float>::over(m.targets.depth.get(), m.targets.depth.size(), ctx.context()());
  map.size = kMapSize;
  map.storage = DepthStorage::Linear;
  map.view = m.view.raster.view;
  map.projection = m.view.raster.projection;
  map.depthNear = m.view.gpu.zNear, map.depthFar = m.view.gpu.zFar;  // the fit's own planes
  return map;
}

CallerGBuffer positionsAndNormals(Context& ctx, const GBuffer& g) {
  CallerGBuffer out;
  out.width = g.width, out.height = g.height;
  out.positions = CallerImage{floats(ctx, g.position)};
  out.normals = CallerImage{floats(ctx, g.normal)};
  return out;
}

Params fixedParams(const TechniqueInfo& info) {
  Params params(info.params);
  params.set("map-size", std::to_string(kMapSize));
  params.set("fit", "scene");
  // A caller's map has no record of the tiles no caster reaches: vssm's HSM is the whole map's (docs/library.md).
  if (info.name == "vssm") params.set("vssm-hsm", "all");
  return params;
}

// The Renderer's visibility, rows from the bottom like the caller's buffers.
std::vector<float> rendererVisibility(const Image& image) {
  const ImageChannel& top = image.require("visibility.Y");
  const int w = image.width(), h = image.height();
  std::vector<float> out(top.data.size());
  for (int y = 0; y < h; ++y) std::copy_n(&top.data[size_t(h - 1 - y) * w], w, &out[size_t(y) * w]);
  return out;
}

struct Difference {
  float max = 0;
  double mean = 0;
  size_t above = 0;  // pixels differing by more than 0.1
};

Difference difference(const std::vector<float>& a, const std::vector<float>& b) {
  Difference d;
  for (size_t i = 0; i < a.size(); ++i) {
    const float e = std::abs(a[i] - b[i]);
    d.max = std::max(d.max, std::isnan(e) ? INFINITY : e);
    d.mean += e;
    d.above += e > 0.1f;
  }
  d.mean /= static_cast<double>(a.size());
  return d;
}

class CallerShade : public test::ClTest {
 protected:
  // The Renderer's frame and, for the same light, its map and G-buffer drawn as the Renderer draws them.
  void prepare(const Staged& s, const Light& light) {
    raster_ = std::make_unique<Rasterizer>(ctx());
    uploadScene(*raster_, s.scene);
    map_ = drawMap(*raster_, s.scene, light);
    castersMap_ = drawMap(*raster_, s.scene, light, true);
    raster_->drawGBuffer(cameraView(s.camera, s.scene.bounds()), gbuffer_);
  }

  std::vector<float> shade(CallerShader& shader, const TechniqueInfo& info, const Params& params, const Light& light,
                           const CallerLightMap& map, const CallerGBuffer& g, const Bounds& bounds) {
    Buffer<float> out(ctx(), size_t(g.width) * g.height);
    out.fill(ctx(), NAN);  // poisoned: every pixel must be written
    CallerImage visibility{Buffer<float>::over(out.get(), out.size(), ctx().context()())};
    shader.shade(info, params, light, map, g, bounds, visibility);
    return out.download(ctx());
  }

  // pcss at fixed settings on the Renderer's map and G-buffer for `light` (prepared): what the variants compare with.
  struct PcssBaseline {
    const TechniqueInfo& pcss = findTechnique("pcss");
    Params params{fixedParams(pcss)};
    CallerLightMap map;
    CallerGBuffer gbuffer;
    std::vector<float> visibility;
  };
  PcssBaseline pcssBaseline(CallerShader& shader, const Staged& s, const Light& light) {
    prepare(s, light);
    PcssBaseline b;
    b.map = linearMap(ctx(), map_);
    b.gbuffer = positionsAndNormals(ctx(), gbuffer_);
    b.visibility = shade(shader, b.pcss, b.params, light, b.map, b.gbuffer, s.scene.bounds());
    return b;
  }

  std::unique_ptr<Rasterizer> raster_;
  DrawnMap map_, castersMap_;
  GBuffer gbuffer_;
};

TEST_F(CallerShade, EveryOneMapTechniqueGivesTheRenderersVisibility) {
  const Staged s = staircase();
  CallerShader shader(ctx());
  size_t techniquesTried = 0;
  for (const Light& light : areaLights(s.scene)) {
    prepare(s, light);
    for (const TechniqueInfo& info : techniques()) {
      if (!info.callerMapRefusal.empty()) continue;
      ++techniquesTried;
      const Params params = fixedParams(info);
      Renderer renderer(ctx(), s.scene);
      const std::vector<float> want = rendererVisibility(renderer.render(s.camera, light, info, params).image);
      const DrawnMap& map = drawsCastersOnly(info.name) ? castersMap_ : map_;  // the map the renderer draws
      const std::vector<float> got = shade(shader, info, params, light, linearMap(ctx(), map),
                                           positionsAndNormals(ctx(), gbuffer_), s.scene.bounds());
      const Difference d = difference(got, want);
      EXPECT_LE(d.max, kSameMapTolerance) << info.name << " light " << light.describe() << " mean " << d.mean;
      EXPECT_EQ(std::count_if(got.begin(), got.end(), [](float v) { return !(v >= 0.0f && v <= 1.0f); }), 0)
          << info.name;
    }
  }
  EXPECT_EQ(techniquesTried, 2u * 11u);  // sm pcf pcss vsm evsm2 evsm4 esm msm savsm vssm lvsm, two lights
}

// The map as a depth buffer would hold it: window values of `projection` in `ndc`'s convention, `clear` where empty.
std::vector<float> windowDepths(const std::vector<float>& linear, const glm::mat4& projection, NdcDepth ndc,
                                float clear) {
  std::vector<float> out(linear.size());
  for (size_t i = 0; i < linear.size(); ++i) {
    if (std::isinf(linear[i])) {
      out[i] = clear;
      continue;
    }
    const glm::vec4 clip = projection * glm::vec4(0.0f, 0.0f, -linear[i], 1.0f);
    const float z = clip.z / clip.w;
    out[i] = ndc == NdcDepth::ZeroToOne ? z : 0.5f * z + 0.5f;
  }
  return out;
}

// Rows of `packed` (width floats each, from the bottom) laid out as a caller might: `offset` floats of padding first,
// rows `pitch` floats apart, the top row first when `topDown`.
std::vector<float> pitched(const std::vector<float>& packed, int width, int height, int channels, size_t offset,
                           size_t pitch, bool topDown) {
  std::vector<float> out(offset + pitch * height, -7.0f);
  const size_t row = size_t(width) * channels;
  for (int y = 0; y < height; ++y)
    std::copy_n(&packed[y * row], row, &out[offset + (topDown ? height - 1 - y : y) * pitch]);
  return out;
}

TEST_F(CallerShade, DepthConventionsAndLayoutsGiveTheLinearMapsVisibility) {
  const Staged s = staircase();
  const Light spot = areaLights(s.scene)[0];
  CallerShader shader(ctx());
  const PcssBaseline base = pcssBaseline(shader, s, spot);
  const std::vector<float> depths = map_.targets.depth.download(ctx());

  struct Case {
    const char* name;
    NdcDepth ndc;
    bool reversed;
  };
  for (const Case c :
       {Case{"OpenGL window depth", NdcDepth::MinusOneToOne, false},
        Case{"zero-to-one window depth", NdcDepth::ZeroToOne, false}, Case{"reversed Z", NdcDepth::ZeroToOne, true}}) {
    CallerLightMap map = base.map;
    map.storage = DepthStorage::Window;
    map.ndc = c.ndc;
    if (c.ndc == NdcDepth::ZeroToOne) {  // the OpenGL projection's z row remapped to [0, 1], then reversed
      for (int col = 0; col < 4; ++col)
        map.projection[col][2] = 0.5f * (base.map.projection[col][2] + base.map.projection[col][3]);
      if (c.reversed)
        for (int col = 0; col < 4; ++col) map.projection[col][2] = base.map.projection[col][3] - map.projection[col][2];
    }
    const std::vector<float> window = windowDepths(depths, map.projection, c.ndc, c.reversed ? 0.0f : 1.0f);
    Buffer<float> texels(ctx(), std::span<const float>(window));
    map.depth.buffer = Buffer<float>::over(texels.get(), texels.size(), ctx().context()());
    const Difference d =
        difference(shade(shader, base.pcss, base.params, spot, map, base.gbuffer, s.scene.bounds()), base.visibility);
    // A window value holds the depth to its float resolution (measured: at most 4.8e-7 apart in visibility).
    EXPECT_LE(d.max, 1e-5f) << c.name;
  }

  // Every image padded, pitched and top-down: the same visibility, written where the layout says and nowhere else.
  const int w = base.gbuffer.width, h = base.gbuffer.height;
  const std::vector<float> mapRows = pitched(depths, kMapSize, kMapSize, 1, 13, kMapSize + 5, true);
  const std::vector<float> positionRows =
      pitched(floats(ctx(), gbuffer_.position).download(ctx()), w, h, 4, 8, size_t(w) * 4 + 12, true);
  const std::vector<float> normalRows =
      pitched(floats(ctx(), gbuffer_.normal).download(ctx()), w, h, 4, 4, size_t(w) * 4 + 4, true);
  Buffer<float> mapBuffer(ctx(), std::span<const float>(mapRows));
  Buffer<float> positionBuffer(ctx(), std::span<const float>(positionRows));
  Buffer<float> normalBuffer(ctx(), std::span<const float>(normalRows));
  CallerLightMap map = base.map;
  map.depth = {Buffer<float>::over(mapBuffer.get(), mapBuffer.size(), ctx().context()()), 13 * 4, (kMapSize + 5) * 4,
               true};
  CallerGBuffer pitchedG = base.gbuffer;
  pitchedG.positions = CallerImage{Buffer<float>::over(positionBuffer.get(), positionBuffer.size(), ctx().context()()),
                                   8 * 4, (size_t(w) * 4 + 12) * 4, true};
  pitchedG.normals = CallerImage{Buffer<float>::over(normalBuffer.get(), normalBuffer.size(), ctx().context()()), 4 * 4,
                                 (size_t(w) * 4 + 4) * 4, true};
  const size_t outOffset = 3, outPitch = size_t(w) + 7;
  Buffer<float> out(ctx(), outOffset + outPitch * h);
  out.fill(ctx(), -7.0f);
  CallerImage visibility{Buffer<float>::over(out.get(), out.size(), ctx().context()()), outOffset * 4, outPitch * 4,
                         true};
  shader.shade(base.pcss, base.params, spot, map, pitchedG, s.scene.bounds(), visibility);
  EXPECT_EQ(out.download(ctx()), pitched(base.visibility, w, h, 1, outOffset, outPitch, true));
}

TEST_F(CallerShade, AGBufferFromDepthAndNormalsFromPositionsComeClose) {
  const Staged s = staircase();
  for (const Light& light : areaLights(s.scene)) {
    CallerShader shader(ctx());
    const PcssBaseline base = pcssBaseline(shader, s, light);

    // Normals from the positions' neighbours: the staircase's faces are flat, so only pixels at edges differ.
    CallerGBuffer derived = base.gbuffer;
    derived.normals.reset();
    const Difference fromPositions =
        difference(shade(shader, base.pcss, base.params, light, base.map, derived, s.scene.bounds()), base.visibility);
    // Measured: mean 2.8e-4 and 2.4e-4, 27 and 6 pixels of 24,000 off by more than 0.1 (stair edges).
    EXPECT_LE(fromPositions.mean, 1e-3) << light.describe();
    EXPECT_LE(fromPositions.above, base.visibility.size() / 200) << light.describe();

    // Positions from a depth buffer and the inverse view-projection (OpenGL convention, cleared to 1).
    const RasterView view = cameraView(s.camera, s.scene.bounds());
    const std::vector<float> depth =
        windowDepths(gbuffer_.depth.download(ctx()), view.projection, NdcDepth::MinusOneToOne, 1.0f);
    Buffer<float> depthBuffer(ctx(), std::span<const float>(depth));
    CallerGBuffer fromDepth;
    fromDepth.width = base.gbuffer.width, fromDepth.height = base.gbuffer.height;
    fromDepth.depth = CallerImage{Buffer<float>::over(depthBuffer.get(), depthBuffer.size(), ctx().context()())};
    fromDepth.inverseViewProjection = glm::inverse(view.projection * view.view);
    fromDepth.normals = base.gbuffer.normals;
    const Difference d = difference(shade(shader, base.pcss, base.params, light, base.map, fromDepth, s.scene.bounds()),
                                    base.visibility);
    // A position off by the depth buffer's resolution moves pcss's taps by as much: at most a few pixels, where a
    // search tap lands on either side of a blocker's edge, change by more than 0.1 (with today's per-pixel tap counts,
    // measured: mean 2.2e-5 and 5.3e-5, 1 pixel of 24,000 each; with fixed 8 x 8 taps at most 0.028 apart).
    EXPECT_LE(d.mean, 2e-4) << light.describe();
    EXPECT_LE(d.above, base.visibility.size() / 2000) << light.describe();
    std::printf("  %s: from depth, mean %.2g, %zu pixels above 0.1, max %.3f\n", light.describe().c_str(), d.mean,
                d.above, d.max);
  }
}

TEST_F(CallerShade, InputsThatCannotWorkAreRefusedByName) {
  const Staged s = staircase();
  const Light spot = areaLights(s.scene)[0];
  prepare(s, spot);
  CallerShader shader(ctx());
  const CallerLightMap map = linearMap(ctx(), map_);
  const CallerGBuffer g = positionsAndNormals(ctx(), gbuffer_);
  Buffer<float> out(ctx(), size_t(g.width) * g.height);
  CallerImage visibility{Buffer<float>::over(out.get(), out.size(), ctx().context()())};
  const TechniqueInfo& pcf = findTechnique("pcf");
  auto refused = [&](const TechniqueInfo& info, const Params& params, const Light& light, const CallerLightMap& m,
                     const CallerGBuffer& gb, CallerImage& v, const std::string& words) {
    try {
      shader.shade(info, params, light, m, gb, s.scene.bounds(), v);
      ADD_FAILURE() << "not refused: " << words;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  const Params pcfParams = fixedParams(pcf);
  for (const char* name : {"pssm", "psvsm", "jittered", "fvsm", "izb"}) {
    const TechniqueInfo& info = findTechnique(name);
    refused(info, Params(info.params), spot, map, g, visibility, std::string("technique ") + name + " cannot shade");
  }
  Light point = spot;
  point.type = LightType::Point;
  refused(pcf, pcfParams, point, map, g, visibility, "point light");
  Light sun = parseLight("dir:0,-1,0");
  refused(pcf, pcfParams, sun, map, g, visibility, "orthographic");
  Params lispsm = fixedParams(findTechnique("sm"));
  lispsm.set("warp", "lispsm");
  refused(findTechnique("sm"), lispsm, spot, map, g, visibility, "warp lispsm");
  Params ids = pcfParams;
  ids.set("id-buffer", "object");
  refused(pcf, ids, spot, map, g, visibility, "id-buffer");

  CallerLightMap stretched = map;
  stretched.projection[1][1] *= 1.5f;
  refused(pcf, pcfParams, spot, stretched, g, visibility, "not square");
  CallerLightMap infinite = map;
  infinite.projection = glm::infinitePerspective(1.0f, 1.0f, 0.1f);
  infinite.depthNear = infinite.depthFar = 0;
  refused(pcf, pcfParams, spot, infinite, g, visibility, "infinite far plane");
  CallerLightMap scaled = map;
  scaled.view = glm::scale(map.view, glm::vec3(2.0f));
  refused(pcf, pcfParams, spot, scaled, g, visibility, "not a rotation");
  CallerLightMap wrongRange = map;
  wrongRange.depthFar *= 2.0f;
  refused(pcf, pcfParams, spot, wrongRange, g, visibility, "not the projection's planes");
  CallerLightMap large = map;
  large.size = kMapSize * 2;
  refused(pcf, pcfParams, spot, large, g, visibility, "past the buffer's");
  CallerLightMap shortRows = map;
  shortRows.depth.rowPitchBytes = 4 * (kMapSize - 1);
  refused(pcf, pcfParams, spot, shortRows, g, visibility, "shorter than a row");
  CallerLightMap odd = map;
  odd.depth.offsetBytes = 2;
  refused(pcf, pcfParams, spot, odd, g, visibility, "multiples of 4 bytes");

  CallerGBuffer both = g;
  both.depth = g.positions;
  refused(pcf, pcfParams, spot, map, both, visibility, "not both or neither");
  CallerGBuffer empty = g;
  empty.width = 0;
  refused(pcf, pcfParams, spot, map, empty, visibility, "at least 1");
  CallerImage small{Buffer<float>::over(out.get(), out.size() - 1, ctx().context()())};
  refused(pcf, pcfParams, spot, map, g, small, "visibility:");
}

}  // namespace caller_shade_test
}  // namespace penumbra
