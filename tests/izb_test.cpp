// The irregular z-buffer (`izb`, kernels/izb.cl): the rasterizer's conservative tile lists against an exact
// point-in-triangle test, and izb's visibility against the Embree reference's hard shadows on every builtin scene
// (spot, sun and point lights, alpha-masked casters), with the disagreements bounded to points next to a shadow
// boundary; sub-pixel samples, chunked passes, and determinism.
#include "kernels/shared/izb.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/gtc/matrix_transform.hpp>
#include <numeric>
#include <random>
#include <tuple>

#include "host/scene/camera.h"
#include "host/scene/procedural.h"
#include "host/scene/procedural_mesh.h"
#include "host/techniques/izb_pattern.h"
#include "host/techniques/registry.h"
#include "host/views/raster_scene.h"
#include "host/views/views.h"
#include "kernels/shared/shadow_ray.h"
#include "raster/rasterizer.h"
#include "tests/support/cl_test.h"
#include "tests/support/render.h"
#include "tools/reference/reference.h"
#include "tools/reference/tracer.h"
#include "tools/selftest/reference/analytic_scenes.h"

namespace penumbra {
namespace izb_test {

using test::renderWith;

TEST(IzbConstants, RayOffsetIsTheReferenceTracers) {
  EXPECT_EQ(SHADOW_RAY_OFFSET, reference::ShadowTracer::kRayOffset);
}

class Izb : public test::ClTest {};

// ---- Conservative tile lists --------------------------------------------------------------------------------

// Window position (pixels) of world point p through clip matrix M, in double; false in front of the near plane.
bool windowOf(const glm::dmat4& M, const glm::vec3& p, int w, int h, glm::dvec2& out) {
  const glm::dvec4 c = M * glm::dvec4(glm::dvec3(p), 1.0);
  if (!(c.w > 0.0 && c.z >= -c.w)) return false;
  out = {(c.x / c.w + 1.0) * 0.5 * w, (c.y / c.w + 1.0) * 0.5 * h};
  return true;
}

// Whether window point q lies inside (or on) the triangle a, b, c.
bool insideTriangle(glm::dvec2 q, glm::dvec2 a, glm::dvec2 b, glm::dvec2 c) {
  auto edge = [](glm::dvec2 u, glm::dvec2 v, glm::dvec2 x) {
    return (v.x - u.x) * (x.y - u.y) - (v.y - u.y) * (x.x - u.x);
  };
  const double e0 = edge(a, b, q), e1 = edge(b, c, q), e2 = edge(c, a, q);
  return (e0 >= 0 && e1 >= 0 && e2 >= 0) || (e0 <= 0 && e1 <= 0 && e2 <= 0);
}

// Random triangles (large, small, sub-pixel, slivers, some crossing the near plane) over a 203x137 viewport (tiles cut
// by its edges), perspective and orthographic: every point inside a triangle's exact projection (random points, the
// vertices, points on its edges) finds the triangle in the list of the tile it falls in, and lists stay near the
// triangles' dilated bounding boxes in size.
TEST_F(Izb, ConservativeTileListsHoldEveryTriangleOverAPoint) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  Scene scene;
  for (int t = 0; t < 400; ++t) {
    const glm::vec3 centre(2.0f * unit(rng), 2.0f * unit(rng), -4.0f + 2.5f * unit(rng));
    const float size = t % 4 == 0 ? 2.0f : t % 4 == 1 ? 0.3f : t % 4 == 2 ? 0.004f : 0.05f;
    const glm::vec3 stretch = t % 7 == 0 ? glm::vec3(3.0f, 0.01f, 1.0f) : glm::vec3(1.0f);
    const auto base = static_cast<uint32_t>(scene.positions.size());
    for (int k = 0; k < 3; ++k)
      scene.positions.push_back(centre + size * stretch * glm::vec3(unit(rng), unit(rng), unit(rng)));
    if (t % 50 == 0) scene.positions.back().z = 3.0f;  // behind the eye: clipped at the near plane (not checked)
    scene.triangles.push_back({base, base + 1, base + 2});
  }
  Rasterizer raster(ctx());
  uploadScene(raster, scene);
  for (bool perspective : {true, false}) {
    RasterView view;
    view.width = 203, view.height = 137;
    view.view = glm::mat4(1.0f);
    view.projection = perspective ? glm::perspective(glm::radians(60.0f), 203.0f / 137.0f, 0.5f, 20.0f)
                                  : glm::ortho(-3.0f, 3.0f, -2.0f, 2.0f, 0.5f, 20.0f);
    const RasterTileLists lists = raster.drawTileLists(view);
    ASSERT_EQ(lists.tilesX, 26);
    ASSERT_EQ(lists.tilesY, 18);
    const std::vector<uint32_t> count = lists.count->download(ctx()), offset = lists.offset->download(ctx());
    const std::vector<uint32_t> entries = lists.entries->download(ctx());
    auto listed = [&](int tile, uint32_t triangle) {
      for (uint32_t e = offset[tile]; e < offset[tile] + count[tile]; ++e)
        if (entries[e] == triangle) return true;
      return false;
    };
    const glm::dmat4 M(rasterClipMatrix(view));
    size_t checked = 0, missing = 0;
    for (uint32_t t = 0; t < scene.triangles.size(); ++t) {
      glm::dvec2 w[3];
      bool front = true;
      for (int k = 0; k < 3; ++k) front = windowOf(M, scene.positions[scene.triangles[t][k]], 203, 137, w[k]) && front;
      if (!front) continue;  // clipped: the exact projection is not the window triangle of its vertices
      std::vector<glm::dvec2> points = {
          w[0], w[1], w[2], (w[0] + w[1]) * 0.5, (w[1] + w[2]) * 0.5, (w[2] + w[0]) * 0.5};
      std::uniform_real_distribution<double> bary(0.0, 1.0);
      for (int s = 0; s < 40; ++s) {
        double a = bary(rng), b = bary(rng);
        if (a + b > 1.0) a = 1.0 - a, b = 1.0 - b;
        points.push_back(w[0] + a * (w[1] - w[0]) + b * (w[2] - w[0]));
      }
      for (const glm::dvec2& q : points) {
        if (!(q.x >= 0 && q.y >= 0 && q.x < 203 && q.y < 137) || !insideTriangle(q, w[0], w[1], w[2])) continue;
        const int tile = static_cast<int>(q.y / 8) * lists.tilesX + static_cast<int>(q.x / 8);
        ++checked;
        if (!listed(tile, t) && ++missing <= 5)
          std::printf("miss: triangle %u (class %u) at (%.3f, %.3f), window %.3f,%.3f %.3f,%.3f %.3f,%.3f\n", t, t % 4,
                      q.x, q.y, w[0].x, w[0].y, w[1].x, w[1].y, w[2].x, w[2].y);
      }
    }
    EXPECT_GT(checked, 2000u);
    EXPECT_EQ(missing, 0u) << (perspective ? "perspective" : "orthographic");
    // No tile lists a triangle that its window bounding box, widened by a pixel, does not reach: lists are not padded
    // beyond the dilation. Triangles clipped at the near plane are left out.
    size_t stray = 0;
    for (int tile = 0; tile < lists.tilesX * lists.tilesY; ++tile)
      for (uint32_t e = offset[tile]; e < offset[tile] + count[tile]; ++e) {
        glm::dvec2 w[3];
        bool front = true;
        for (int k = 0; k < 3; ++k)
          front = windowOf(M, scene.positions[scene.triangles[entries[e]][k]], 203, 137, w[k]) && front;
        if (!front) continue;
        const double x0 = std::min({w[0].x, w[1].x, w[2].x}) - 1, x1 = std::max({w[0].x, w[1].x, w[2].x}) + 1;
        const double y0 = std::min({w[0].y, w[1].y, w[2].y}) - 1, y1 = std::max({w[0].y, w[1].y, w[2].y}) + 1;
        const int tx = tile % lists.tilesX, ty = tile / lists.tilesX;
        stray += tx * 8 > x1 || tx * 8 + 8 < x0 || ty * 8 > y1 || ty * 8 + 8 < y0;
      }
    EXPECT_EQ(stray, 0u);
  }
}

// ---- izb against the reference's hard shadows -------------------------------------------------------------

// `light` with no extent: a point, a direction.
Light hard(Light light) {
  light.radius = 0.0f;
  light.angularRadiusDeg = 0.0f;
  return light;
}

struct Agreement {
  size_t covered = 0, wrong = 0, nearBoundary = 0;
};

// izb's visibility against the reference's at every covered pixel. A pixel that disagrees is excused when the
// reference itself changes its answer within `tolerance` of the point: traced again from 8 points on a circle of that
// radius in the surface's plane, one of them disagrees with the centre (the point lies within `tolerance` of a shadow
// boundary). `wrong` counts the others.
Agreement agreement(Context& ctx, const Scene& scene, const Camera& camera, const Light& light,
                    const std::vector<float>& visibility, float tolerance) {
  Rasterizer raster(ctx);
  uploadScene(raster, scene);
  GBuffer g;
  raster.drawGBuffer(cameraView(camera, scene.bounds()), g);
  const std::vector<cl_float4> position = g.position.download(ctx);
  const std::vector<uint32_t> triangle = g.triangleId.download(ctx);
  std::vector<reference::ShadowPoint> points;
  std::vector<size_t> pixelOf;
  for (size_t i = 0; i < position.size(); ++i) {
    if (position[i].s[3] == 0.0f) continue;
    const glm::uvec3 t = scene.triangles[triangle[i]];
    const glm::vec3 a = scene.positions[t[0]], b = scene.positions[t[1]], c = scene.positions[t[2]];
    points.push_back(
        {{position[i].s[0], position[i].s[1], position[i].s[2]}, glm::normalize(glm::cross(b - a, c - a))});
    pixelOf.push_back(i);
  }
  const reference::ShadowTracer tracer(scene);
  const reference::TraceResult truth = tracer.trace(points, light, {});
  Agreement out;
  out.covered = points.size();
  const int w = camera.width, h = camera.height;
  for (size_t k = 0; k < points.size(); ++k) {
    const size_t i = pixelOf[k];
    const size_t row = static_cast<size_t>(h - 1) - i / static_cast<size_t>(w), column = i % static_cast<size_t>(w);
    const float ours = visibility[row * static_cast<size_t>(w) + column];  // the image's rows are top-down
    if (ours == truth.visibility[k]) continue;
    const glm::vec3 n = points[k].normal, u = glm::normalize(glm::cross(n, chooseUp(n))), v = glm::cross(n, u);
    std::vector<reference::ShadowPoint> around;
    for (int s = 0; s < 8; ++s) {
      const float angle = static_cast<float>(s) * 0.7853982f;
      around.push_back({points[k].position + tolerance * (std::cos(angle) * u + std::sin(angle) * v), n});
    }
    const reference::TraceResult near = tracer.trace(around, light, {});
    const bool boundary =
        std::any_of(near.visibility.begin(), near.visibility.end(), [&](float x) { return x != truth.visibility[k]; });
    (boundary ? out.nearBoundary : out.wrong) += 1;
  }
  return out;
}

// Boundary tolerance: 2e-4 of the scene's radius (twice the rays' origin offset): closer than that to a shadow edge,
// float rounding in either tracer may flip a ray. At most 0.5 % of the covered pixels lie that close.
constexpr float kBoundaryTolerance = 2e-4f;
constexpr double kMaxBoundaryShare = 0.005;

void expectExact(Context& ctx, const std::string& label, const Scene& scene, const Camera& camera, const Light& light,
                 const test::Values& values = {}) {
  const RenderResult r = renderWith(ctx, scene, camera, light, "izb", values);
  ASSERT_TRUE(test::saneImage(r.image, label));
  const Agreement a = agreement(ctx, scene, camera, light, r.image.require("visibility.Y").data,
                                kBoundaryTolerance * scene.bounds().radius());
  std::printf("%s: %zu covered, %zu near a boundary, %zu wrong (%s)\n", label.c_str(), a.covered, a.nearBoundary,
              a.wrong, r.image.attributes().at("penumbra:izb").c_str());
  EXPECT_GT(a.covered, 1000u) << label;
  EXPECT_EQ(a.wrong, 0u) << label;
  EXPECT_LE(static_cast<double>(a.nearBoundary), kMaxBoundaryShare * static_cast<double>(a.covered)) << label;
}

TEST_F(Izb, EqualsTheReferencesHardShadowsOnEveryBuiltinScene) {
  for (const ProceduralInfo& info : proceduralScenes()) {
    const Scene scene = makeProcedural(info.name);
    Camera camera = scene.cameras.empty() ? test::topDown() : scene.cameras.front();
    camera.width = 160, camera.height = 96;
    for (size_t l = 0; l < scene.lights.size(); ++l)
      expectExact(ctx(), info.name + " light " + std::to_string(l), scene, camera, hard(scene.lights[l]));
  }
}

// A point light (six cube faces, each a square spot grid) and the scene-fitted grid, on scenes with alpha-masked and
// stacked casters.
TEST_F(Izb, EqualsTheReferenceForPointLightsAndSceneFits) {
  for (const char* name : {"cards", "stacked-planes", "staircase"}) {
    const Scene scene = makeProcedural(name);
    Camera camera = scene.cameras.empty() ? test::topDown() : scene.cameras.front();
    camera.width = 128, camera.height = 80;
    Light point = hard(scene.lights.front());
    if (point.type != LightType::Directional) {
      point.type = LightType::Point;
      expectExact(ctx(), std::string(name) + " point", scene, camera, point);
    }
    expectExact(ctx(), std::string(name) + " fit scene", scene, camera, hard(scene.lights.front()),
                {{"fit", "scene"}, {"map-size", "512"}});
  }
}

// A builtin scene seen by its own camera at width x height, under its first light made hard.
struct HardFrame {
  Scene scene;
  Camera camera;
  Light light;
};
HardFrame hardFrame(const char* name, int width, int height) {
  HardFrame f{makeProcedural(name), {}, {}};
  f.camera = f.scene.cameras.front();
  f.camera.width = width, f.camera.height = height;
  f.light = hard(f.scene.lights.front());
  return f;
}

// Chunked passes (a chunk far smaller than the frame: several draws) give the image of one pass, bit for bit; the
// grid's size changes the lists, not the answer.
TEST_F(Izb, ChunksAndGridSizesDoNotChangeTheResult) {
  const auto [scene, camera, light] = hardFrame("cards", 96, 64);
  const RenderResult one = renderWith(ctx(), scene, camera, light, "izb");
  const auto& expected = one.image.require("visibility.Y").data;
  for (const test::Values& values : {test::Values{{"izb-chunk", "1000"}}, test::Values{{"map-size", "128"}},
                                     test::Values{{"map-size", "4096"}}, test::Values{{"map-size", "203"}}}) {
    const RenderResult other = renderWith(ctx(), scene, camera, light, "izb", values);
    EXPECT_EQ(other.image.require("visibility.Y").data, expected) << values.begin()->first;
  }
  const RenderResult chunked = renderWith(ctx(), scene, camera, light, "izb", {{"izb-chunk", "1000"}});
  EXPECT_NE(chunked.image.attributes().at("penumbra:izb").find(" in 7 chunks"), std::string::npos)
      << chunked.image.attributes().at("penumbra:izb");
}

// Sub-pixel samples: values are multiples of 1/S; a pixel whose 3x3 neighbourhood is uniformly lit or shadowed at one
// sample keeps that value at S samples (its footprint lies inside the region), up to thin features; fractional values
// only along the one-sample image's boundaries.
TEST_F(Izb, SubPixelSamplesAntialiasOnlyAtShadowBoundaries) {
  const auto [scene, camera, light] = hardFrame("box", 160, 96);
  const RenderResult single = renderWith(ctx(), scene, camera, light, "izb");
  const auto& one = single.image.require("visibility.Y").data;
  const int w = camera.width, h = camera.height;
  for (int samples : {4, 8, 32}) {
    const RenderResult r = renderWith(ctx(), scene, camera, light, "izb", {{"izb-samples", std::to_string(samples)}});
    ASSERT_TRUE(test::saneImage(r.image, "samples"));
    const auto& many = r.image.require("visibility.Y").data;
    size_t interior = 0, changed = 0, fractional = 0, fractionalOffEdge = 0;
    for (int y = 1; y + 1 < h; ++y)
      for (int x = 1; x + 1 < w; ++x) {
        const size_t i = static_cast<size_t>(y) * w + x;
        const float v = many[i] * static_cast<float>(samples);
        EXPECT_NEAR(v, std::round(v), 1e-3f);
        bool uniform = true;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) uniform = uniform && one[i + dy * w + dx] == one[i];
        const bool frac = many[i] > 0.0f && many[i] < 1.0f;
        fractional += frac;
        if (uniform) {
          ++interior;
          changed += many[i] != one[i];
          fractionalOffEdge += frac;
        }
      }
    std::printf("%d samples: %zu fractional pixels, %zu of %zu interior pixels changed\n", samples, fractional, changed,
                interior);
    EXPECT_GT(fractional, 50u) << samples;  // the box's and the plate's shadow edges are antialiased
    EXPECT_LE(changed, interior / 200) << samples;
    EXPECT_LE(fractionalOffEdge, fractional / 10) << samples;
  }
}

TEST_F(Izb, RefusesUnsupportedSampleCountsAndIsDeterministic) {
  const auto [scene, camera, light] = hardFrame("poles", 64, 48);
  Params params(findTechnique("izb").params);
  EXPECT_THROW(params.set("izb-samples", "3"), std::invalid_argument);
  EXPECT_THROW(params.set("izb-samples", "64"), std::invalid_argument);
  const RenderResult a = renderWith(ctx(), scene, camera, light, "izb", {{"izb-samples", "8"}});
  const RenderResult b = renderWith(ctx(), scene, camera, light, "izb", {{"izb-samples", "8"}});
  EXPECT_EQ(a.image.require("visibility.Y").data, b.image.require("visibility.Y").data);
}

// ---- Area lights: N light points per sample -----------------------------------------------------------------

// `light` given an extent where it has none: a disk or sphere of radius `radius`, a sun of 3 degrees.
Light area(Light light, float radius = 0.3f) {
  if (light.type == LightType::Directional) {
    if (light.angularRadiusDeg == 0.0f) light.angularRadiusDeg = 3.0f;
  } else if (light.radius == 0.0f) {
    light.radius = radius;
  }
  return light;
}

// izb's soft visibility and the reference traced through the same N light points per pixel (TraceSettings
// izbLightGrid: the same rays), at every covered pixel: `differing` counts the rays they disagree on (at least
// |difference| * N per pixel).
struct RayAgreement {
  size_t pixels = 0, differing = 0;
  uint64_t rays = 0;
  std::string izb;  // the izb header
};
RayAgreement sameRays(Context& ctx, const Scene& scene, const Camera& camera, const Light& light, int n,
                      test::Values values = {}) {
  values["izb-light-samples"] = std::to_string(n);
  const RenderResult r = renderWith(ctx, scene, camera, light, "izb", values);
  EXPECT_TRUE(test::saneImage(r.image, "izb soft"));
  reference::TraceSettings settings;
  settings.izbLightGrid = izb_light_grid_of(n);
  const reference::ReferenceResult truth = reference::renderReference(ctx, scene, camera, light, settings);
  const auto& ours = r.image.require("visibility.Y").data;
  const auto& theirs = truth.image.require("visibility.Y").data;
  const auto& covered = truth.image.require("depth.Z").data;
  RayAgreement a;
  a.izb = r.image.attributes().at("penumbra:izb");
  for (size_t i = 0; i < ours.size(); ++i) {
    if (!std::isfinite(covered[i])) continue;
    ++a.pixels;
    a.rays += static_cast<uint64_t>(n);
    a.differing += static_cast<size_t>(std::lround(std::abs(ours[i] - theirs[i]) * static_cast<float>(n)));
  }
  return a;
}

// At most one ray in 10^4 may differ: both trace the same ray with a watertight test, so only a ray within float
// rounding of a caster's edge (the two compute the ray's direction with different roundings) can.
constexpr double kMaxDifferingRays = 1e-4;

void expectSameRays(Context& ctx, const std::string& label, const Scene& scene, const Camera& camera,
                    const Light& light, int n, const test::Values& values = {}) {
  const RayAgreement a = sameRays(ctx, scene, camera, light, n, values);
  std::printf("%s: %zu pixels, %zu of %llu rays differ (%s)\n", label.c_str(), a.pixels, a.differing,
              static_cast<unsigned long long>(a.rays), a.izb.c_str());
  EXPECT_GT(a.pixels, 1000u) << label;
  EXPECT_NE(a.izb.find("light points per sample"), std::string::npos) << label;
  EXPECT_LE(static_cast<double>(a.differing), kMaxDifferingRays * static_cast<double>(a.rays)) << label;
}

// Every builtin scene under its own light given an extent (spot disks, suns, alpha-masked cards), then spheres (point
// lights: six cube faces) and a sun of 5 degrees, and a scene-fitted grid.
TEST_F(Izb, SoftEqualsTheReferenceTracedWithTheSameLightPoints) {
  for (const ProceduralInfo& info : proceduralScenes()) {
    const Scene scene = makeProcedural(info.name);
    Camera camera = scene.cameras.empty() ? test::topDown() : scene.cameras.front();
    camera.width = 120, camera.height = 72;
    expectSameRays(ctx(), info.name, scene, camera, area(scene.lights.front()), 16);
  }
  for (const char* name : {"cards", "stacked-planes", "staircase"}) {
    const Scene scene = makeProcedural(name);
    Camera camera = scene.cameras.front();
    camera.width = 112, camera.height = 64;
    Light sphere = area(scene.lights.front(), 0.4f);
    if (sphere.type != LightType::Directional) {
      sphere.type = LightType::Point;
      expectSameRays(ctx(), std::string(name) + " sphere", scene, camera, sphere, 25);
    }
    Light sun;
    sun.type = LightType::Directional;
    sun.direction = glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f));
    sun.angularRadiusDeg = 5.0f;
    expectSameRays(ctx(), std::string(name) + " sun", scene, camera, sun, 16);
    expectSameRays(ctx(), std::string(name) + " fit scene", scene, camera, area(scene.lights.front()), 36,
                   {{"fit", "scene"}, {"map-size", "512"}});
  }
}

// Casters the projection cannot take as plain triangles: zero-area ones (a repeated vertex, which no ray meets;
// three distinct collinear vertices), a fan of slivers and walls standing on the receiver (their edges run through the
// ray origins next to them, seen end-on: ill-conditioned lines, decided point by point), random slivers hugging the
// ground, under a spot disk, a sphere and a sun.
TEST_F(Izb, SoftKeepsTheRaysOnDegenerateAndContactCasters) {
  Scene scene = test::squareOverPlane();
  auto add = [&](std::initializer_list<glm::vec3> points) {
    const uint32_t base = static_cast<uint32_t>(scene.positions.size());
    for (const glm::vec3& p : points) scene.positions.push_back(p), scene.normals.push_back({0, 1, 0});
    scene.triangles.push_back({base, base + 1, base + 2});
    scene.objectIds.push_back(1);
  };
  add({{-0.5f, 1.0f, 0.0f}, {-0.5f, 1.0f, 0.0f}, {0.5f, 1.0f, 0.5f}});    // a repeated vertex
  add({{-1.5f, 1.0f, -1.0f}, {0.0f, 1.0f, -1.0f}, {1.5f, 1.0f, -1.0f}});  // collinear
  for (int i = 0; i < 24; ++i) {  // a fan of slivers standing on the ground around (2, 0, 2)
    const float a = 0.2617994f * static_cast<float>(i), b = a + 0.01f;
    add({{2.0f, 0.0f, 2.0f},
         {2.0f + std::cos(a), 0.6f, 2.0f + std::sin(a)},
         {2.0f + std::cos(b), 0.0f, 2.0f + std::sin(b)}});
  }
  add({{-3.0f, 0.0f, 1.0f}, {-1.0f, 0.0f, 1.0f}, {-2.0f, 1.5f, 1.0f}});  // walls on the ground, across each other
  add({{-2.0f, 0.0f, 0.0f}, {-2.0f, 0.0f, 2.0f}, {-2.0f, 1.5f, 1.0f}});
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-3.0f, 3.0f), h(0.0f, 0.05f), d(-0.3f, 0.3f);
  for (int i = 0; i < 200; ++i) {
    const glm::vec3 c(u(rng), h(rng), u(rng));
    add({c, c + glm::vec3(d(rng), h(rng), d(rng)), c + glm::vec3(d(rng), 0.0f, d(rng))});
  }
  Camera camera = test::topDown();
  camera.width = 128, camera.height = 96;
  Light spot = parseLight("spot:0.5,4,0.3:0,0,0:120:0.6");
  expectSameRays(ctx(), "contact spot", scene, camera, spot, 64);
  Light sphere = spot;
  sphere.type = LightType::Point;
  expectSameRays(ctx(), "contact sphere", scene, camera, sphere, 36);
  Light sun;
  sun.type = LightType::Directional;
  sun.direction = glm::normalize(glm::vec3(0.6f, -1.0f, 0.2f));
  sun.angularRadiusDeg = 6.0f;
  expectSameRays(ctx(), "contact sun", scene, camera, sun, 64);
}

// The triangles of closed meshes whose outer side faces away from the whole light are left out of the casters
// (host/scene/solids.h): the rays stay the reference's for a box above the ground, one turned inside out, one sunk
// into the ground (receivers inside it and on it) and a tall one next to the light, under a disk, a sphere and a sun;
// with the light inside a closed box nothing is left out and every ray is blocked.
size_t leftOut(const std::string& header) {
  const size_t at = header.find(" of them facing away");
  EXPECT_NE(at, std::string::npos) << header;
  if (at == std::string::npos) return 0;
  return std::stoul(header.substr(header.rfind(' ', at - 1) + 1));
}

TEST_F(Izb, SoftLeavesOutTheFarSidesOfSolidsAndKeepsTheRays) {
  Scene scene = test::squareOverPlane();
  detail::addBox(scene, detail::addObject(scene, "box"), {1.5f, 0.5f, 1.0f}, {2.5f, 1.5f, 2.0f});
  const size_t inverted = scene.triangles.size();
  detail::addBox(scene, detail::addObject(scene, "inside out"), {-3.0f, 0.3f, 1.0f}, {-2.0f, 1.0f, 2.5f});
  for (size_t t = inverted; t < scene.triangles.size(); ++t) std::swap(scene.triangles[t].y, scene.triangles[t].z);
  detail::addBox(scene, detail::addObject(scene, "sunk"), {-1.0f, -0.5f, 2.5f}, {1.0f, 0.4f, 3.5f});
  detail::addBox(scene, detail::addObject(scene, "tower"), {2.5f, 0.0f, -2.5f}, {3.0f, 3.5f, -2.0f});
  Camera camera = test::topDown();
  camera.width = 128, camera.height = 96;
  Light spot = parseLight("spot:0.5,5,0.3:0,0,0:120:0.6");
  Light sphere = spot;
  sphere.type = LightType::Point;
  Light sun;
  sun.type = LightType::Directional;
  sun.direction = glm::normalize(glm::vec3(0.6f, -1.0f, 0.2f));
  sun.angularRadiusDeg = 6.0f;
  for (const auto& [label, light, n] : {std::tuple{"solids spot", spot, 64}, std::tuple{"solids sphere", sphere, 36},
                                        std::tuple{"solids sun", sun, 64}}) {
    expectSameRays(ctx(), label, scene, camera, light, n);
    const RayAgreement a = sameRays(ctx(), scene, camera, light, 16);
    EXPECT_GE(leftOut(a.izb), 8u) << label;  // at least the bottom and a side of each box
  }
  Scene enclosed = test::squareOverPlane();
  detail::addBox(enclosed, detail::addObject(enclosed, "lamp housing"), {-0.5f, 3.5f, -0.5f}, {0.5f, 4.5f, 0.5f});
  const Light inside = parseLight("spot:0,4,0:0,0,0:120:0.3");
  expectSameRays(ctx(), "light inside a solid", enclosed, camera, inside, 16);
  const RayAgreement a = sameRays(ctx(), enclosed, camera, inside, 16);
  EXPECT_EQ(leftOut(a.izb), 0u);
  EXPECT_EQ(a.differing, 0u);
}

// The grid, the passes and 64 or 256 points do not change the rays: chunks and grid sizes give the same image; more
// points follow the reference as closely.
TEST_F(Izb, SoftChunksGridsAndPatternSizesKeepTheRays) {
  const Scene scene = makeProcedural("stacked-planes");
  Camera camera = scene.cameras.front();
  camera.width = 96, camera.height = 64;
  const Light light = area(scene.lights.front());
  const RenderResult one = renderWith(ctx(), scene, camera, light, "izb");
  for (const test::Values& values : {test::Values{{"izb-chunk", "1000"}}, test::Values{{"map-size", "256"}}}) {
    const RenderResult other = renderWith(ctx(), scene, camera, light, "izb", values);
    EXPECT_EQ(other.image.require("visibility.Y").data, one.image.require("visibility.Y").data)
        << values.begin()->first;
  }
  expectSameRays(ctx(), "stacked-planes 64", scene, camera, light, 64);
  expectSameRays(ctx(), "stacked-planes 256", scene, camera, light, 256);
}

// Against a converged reference (1024 stratified rays a pixel), izb's 64 points are no worse than tracing 64 of the
// reference's own stratified samples: the pattern's sampling error is all that is left.
TEST_F(Izb, SoftErrorIsTheSamplingErrorOfItsPattern) {
  for (const char* name : {"staircase", "stacked-planes"}) {
    const Scene scene = makeProcedural(name);
    Camera camera = scene.cameras.front();
    camera.width = 160, camera.height = 96;
    const Light light = area(scene.lights.front());
    const RenderResult r = renderWith(ctx(), scene, camera, light, "izb");
    const auto& ours = r.image.require("visibility.Y").data;
    const auto truth = reference::renderReference(ctx(), scene, camera, light, {1024, 1, 0});
    const auto traced = reference::renderReference(ctx(), scene, camera, light, {64, 2, 0});
    const auto& exact = truth.image.require("visibility.Y").data;
    const auto& sixtyFour = traced.image.require("visibility.Y").data;
    const auto& covered = truth.image.require("depth.Z").data;
    double izbError = 0, tracedError = 0;
    size_t pixels = 0;
    for (size_t i = 0; i < ours.size(); ++i) {
      if (!std::isfinite(covered[i])) continue;
      ++pixels;
      izbError += std::abs(ours[i] - exact[i]), tracedError += std::abs(sixtyFour[i] - exact[i]);
    }
    izbError /= static_cast<double>(pixels), tracedError /= static_cast<double>(pixels);
    std::printf("%s: MAE against 1024 spp: izb (64 points) %.6f, the reference at 64 spp %.6f\n", name, izbError,
                tracedError);
    EXPECT_GT(tracedError, 0.0) << name;  // the scene has penumbrae
    EXPECT_LE(izbError, tracedError * 1.05) << name;
  }
}

// Sub-pixel samples each draw their own turn of the pattern: values are multiples of 1 / (S N), and the image stays
// within the sampling noise of one sample's.
TEST_F(Izb, SoftSubPixelSamplesCombineWithLightPoints) {
  const Scene scene = makeProcedural("box");
  Camera camera = scene.cameras.front();
  camera.width = 96, camera.height = 64;
  const Light light = area(scene.lights.front());
  const RenderResult single = renderWith(ctx(), scene, camera, light, "izb", {{"izb-light-samples", "16"}});
  const auto& one = single.image.require("visibility.Y").data;
  const RenderResult four =
      renderWith(ctx(), scene, camera, light, "izb", {{"izb-light-samples", "16"}, {"izb-samples", "4"}});
  ASSERT_TRUE(test::saneImage(four.image, "izb soft 4 samples"));
  const auto& many = four.image.require("visibility.Y").data;
  double difference = 0;
  for (size_t i = 0; i < many.size(); ++i) {
    const float v = many[i] * 64.0f;
    EXPECT_NEAR(v, std::round(v), 1e-3f) << i;
    difference += std::abs(many[i] - one[i]);
  }
  EXPECT_LT(difference / static_cast<double>(many.size()), 0.01);
}

TEST_F(Izb, SoftRefusesPatternSizesThatAreNoSquare) {
  const Scene scene = makeProcedural("box");
  Camera camera = scene.cameras.front();
  camera.width = 32, camera.height = 24;
  for (const char* n : {"20", "15", "289"}) {
    Params params(findTechnique("izb").params);
    bool refused = false;
    try {
      params.set("izb-light-samples", n);
      renderWith(ctx(), scene, camera, area(scene.lights.front()), "izb", {{"izb-light-samples", n}});
    } catch (const std::invalid_argument&) {
      refused = true;
    }
    EXPECT_TRUE(refused) << n;
  }
}

// The CPU work-group spread (IzbFrame::spread) is a permutation of the groups for every count, and deals each of the
// runtime's runs of consecutive groups (PoCL's: up to 512) blocks from the whole range, so a dense prefix is shared.
TEST(IzbConstants, SpreadStridePermutesTheGroupsAndSharesAPrefix) {
  for (uint32_t groups = 1; groups <= 5000; ++groups) {
    const uint32_t stride = izb_spread_stride(groups);
    ASSERT_EQ(std::gcd(stride, groups), 1u) << groups;
    std::vector<bool> seen(groups, false);
    for (uint32_t g = 0; g < groups; ++g) seen[static_cast<uint64_t>(g) * stride % groups] = true;
    ASSERT_EQ(std::count(seen.begin(), seen.end(), true), static_cast<std::ptrdiff_t>(groups)) << groups;
  }
  // 3600 groups (640x360 samples), the work in the first 1400: each run of 512 gets 150-250 of them, not 0 or 512.
  const uint32_t groups = 3600, stride = izb_spread_stride(groups);
  for (uint32_t run = 0; run + 512 <= groups; run += 512) {
    int dense = 0;
    for (uint32_t g = run; g < run + 512; ++g) dense += static_cast<uint64_t>(g) * stride % groups < 1400;
    EXPECT_GT(dense, 150) << run;
    EXPECT_LT(dense, 250) << run;
  }
}

// The pattern's bitmask tables against the points themselves: for random edges (normal angle, offset) across the
// light's plane, every point within the margin of the inner side is in the "may" mask of the edge's bin, and every
// point of the "certain" mask lies inside by more than the margin; for disk and sun points, turned patterns too.
TEST(IzbPattern, BitmaskTablesAreConservative) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> angle(-3.14159265358979, 3.14159265358979), offset(-1.2, 1.2);
  for (int grid : {4, 8, 16}) {
    const IzbLightPattern pattern(grid);
    const int n = pattern.count(), words = izb_mask_words(n);
    for (const glm::vec2& p : pattern.points()) EXPECT_LE(glm::length(p), 1.0f + 1e-6f);
    for (bool sun : {false, true}) {
      const float oneMinusCos = sun ? 1.0f - std::cos(glm::radians(10.0f)) : 0.0f;
      const std::vector<uint32_t> masks = pattern.masks(sun, oneMinusCos, IZB_MASK_MARGIN);
      ASSERT_EQ(masks.size(), static_cast<size_t>(IZB_MASK_ANGLES) * IZB_MASK_OFFSETS * 2 * words);
      const double tanAlpha = std::tan(glm::radians(10.0));
      size_t certain = 0, maybe = 0;
      for (int trial = 0; trial < 2000; ++trial) {
        const uint32_t key = static_cast<uint32_t>(rng());
        const double a = angle(rng), d = offset(rng);
        const glm::dvec2 normal(std::cos(a), std::sin(a));
        // The lookup of kernels/izb.cl izb_edge_tables, the edge turned back by the key's rotation.
        const glm::vec2 cs = pattern.rotations()[izb_rotation_of(key)];
        const glm::vec2 e(normal);
        const int bin = izb_mask_angle_bin(cs.x * e.x + cs.y * e.y, cs.x * e.y - cs.y * e.x);
        const int b =
            std::clamp(static_cast<int>(std::floor((d + 1.0) * 0.5 * IZB_MASK_OFFSETS)), 0, IZB_MASK_OFFSETS - 1);
        const uint32_t* may = &masks[((static_cast<size_t>(bin) * IZB_MASK_OFFSETS + b) * 2) * words];
        for (int j = 0; j < n; ++j) {
          glm::dvec2 q(pattern.point(key, j));
          if (sun) {  // the direction's tangent over tan(alpha), as the kernel's plane holds it
            const double r = glm::length(q), x = r * r * oneMinusCos;
            if (r > 0.0) q *= std::sqrt(x * (2.0 - x)) / (1.0 - x) / (tanAlpha * r);
          }
          const double s = glm::dot(normal, q) - d;
          const bool inMay = (may[j / 32] >> (j % 32)) & 1u, inCertain = (may[words + j / 32] >> (j % 32)) & 1u;
          if (s >= -IZB_MASK_MARGIN * 0.5) {
            EXPECT_TRUE(inMay) << grid << " " << sun << " " << j << " " << s;
          }
          if (inCertain) {
            EXPECT_GT(s, IZB_MASK_MARGIN * 0.5) << grid << " " << sun << " " << j;
          }
          certain += inCertain, maybe += inMay;
        }
      }
      EXPECT_GT(certain, 0u);
      EXPECT_GT(maybe, certain);
    }
  }
}

// An empty scene and a frame with no covered pixel: everything lit, nothing outside, no NaN.
TEST_F(Izb, EmptyScenesAreLit) {
  Scene scene = test::squareOverPlane();
  Camera camera = test::topDown();
  camera.width = 32, camera.height = 24;
  camera.target = camera.eye + glm::vec3(0, 1, 0);  // looking up at the sky
  const RenderResult r = renderWith(ctx(), scene, camera, test::pointAbove(), "izb");
  ASSERT_TRUE(test::saneImage(r.image, "sky"));
  for (float v : r.image.require("visibility.Y").data) EXPECT_EQ(v, 1.0f);
}

}  // namespace izb_test
}  // namespace penumbra
