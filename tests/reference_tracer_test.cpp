// The Embree reference (tools/reference/) against analytic answers: a point light's hard edge on exactly the
// ground pixels geometry says, the penumbra of a disk light and of a sun disk over a straight occluder edge
// against their exact profiles (fraction of the disk area / cone solid angle past the edge), a standard error
// that matches the actual error, thread-count determinism, G-buffer pixels identical to `render`'s, and no NaN
// on any built-in scene.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "host/pipeline/renderer.h"
#include "host/scene/procedural.h"
#include "host/techniques/technique.h"
#include "tests/support/cl_test.h"
#include "tests/support/render.h"
#include "tools/reference/light_samples.h"
#include "tools/reference/reference.h"
#include "tools/selftest/reference/analytic_scenes.h"

namespace penumbra::reference {
namespace reference_tracer_test {
using test::ClTest;

constexpr double kPi = std::numbers::pi;
// At 1024 spp (4 replicates of 16x16 strata) an edge crossing the disk leaves ~16 strata partly visible per
// replicate: standard error <= ~0.004 per point. 0.02 is five of those; the mean over the profile is far tighter.
constexpr int kSpp = 1024;
constexpr double kPointTolerance = 0.02;
constexpr double kMeanTolerance = 0.005;
constexpr double kEndMargin = 5e-3;  // world units around the penumbra's ends where 0 and 1 need not be exact

// Receivers on the ground (y = 0, normal up) along x at z = 0.3, away from the occluder's corners.
std::vector<ShadowPoint> groundLine(float x0, float x1, int count) {
  std::vector<ShadowPoint> points;
  for (int i = 0; i < count; ++i)
    points.push_back(
        {{x0 + (x1 - x0) * static_cast<float>(i) / static_cast<float>(count - 1), 0.0f, 0.3f}, {0.0f, 1.0f, 0.0f}});
  return points;
}

// Disk light of radius R at y = 4 over the occluder edge x = 1 at y = 2: the ray from ground point x to the light
// point s crosses y = 2 at (x + s_x) / 2, so s is blocked iff s_x < 2 - x. Visible: the disk area beyond the
// chord at d = 2 - x, i.e. the integral of the chord length 2 sqrt(R^2 - t^2) over t in [d, R], over pi R^2.
double diskVisible(double x, double radius) {
  const double d = std::clamp((2.0 - x) / radius, -1.0, 1.0);
  return (std::acos(d) - d * std::sqrt(1.0 - d * d)) / kPi;
}

// Sun straight down with angular radius alpha: the ray from ground point x in direction (theta, phi) crosses
// y = 2 at x + 2 tan(theta) cos(phi), blocked while that is < 1. For each theta the lit azimuths are analytic;
// integrate over 1 - cos(theta), uniform for uniform solid angle (midpoint rule, 20000 steps).
double sunVisible(double x, double alphaDeg) {
  constexpr int kSteps = 20000;
  const double oneMinusCos = 1.0 - std::cos(alphaDeg * kPi / 180.0);
  double lit = 0;
  for (int i = 0; i < kSteps; ++i) {
    const double cosTheta = 1.0 - (i + 0.5) / kSteps * oneMinusCos;
    const double tanTheta = std::sqrt(1.0 - cosTheta * cosTheta) / cosTheta;
    const double c = tanTheta > 0 ? (1.0 - x) / (2.0 * tanTheta) : (x > 1.0 ? -2.0 : 2.0);
    lit += std::acos(std::clamp(c, -1.0, 1.0)) / kPi;  // fraction of azimuths with cos(phi) > c
  }
  return lit / kSteps;
}

// Checks a traced profile against the exact one: per point, on average, and the reported standard error against
// the actual error (their mean squares within a factor 4 over the penumbra).
void expectProfile(const TraceResult& traced, const std::vector<ShadowPoint>& points, auto exact) {
  double sumAbs = 0, sumSq = 0, sumStderrSq = 0;
  int penumbra = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    const double want = exact(points[i].position.x), got = traced.visibility[i];
    EXPECT_NEAR(got, want, kPointTolerance) << "x = " << points[i].position.x;
    sumAbs += std::abs(got - want);
    if (want == 0.0 || want == 1.0) {         // outside the penumbra every sample agrees (the ray offset moves its
      const double x = points[i].position.x;  // ends by < 4e-4: checked 5e-3 away from them)
      if (exact(x - kEndMargin) == want && exact(x + kEndMargin) == want) {
        EXPECT_EQ(got, want) << "x = " << x;
        EXPECT_EQ(traced.standardError[i], 0.0f) << "x = " << x;
      }
      continue;
    }
    sumSq += (got - want) * (got - want), sumStderrSq += traced.standardError[i] * traced.standardError[i];
    ++penumbra;
  }
  EXPECT_LT(sumAbs / static_cast<double>(points.size()), kMeanTolerance);
  ASSERT_GT(penumbra, 10);
  const double ratio = sumSq / sumStderrSq;
  EXPECT_GT(ratio, 0.25) << "standard error overstated";
  EXPECT_LT(ratio, 4.0) << "standard error understated";
}

TEST(ReferenceTracer, DiskLightPenumbraMatchesTheExactProfile) {
  const ShadowTracer tracer(test::squareOverPlane());
  const std::vector<ShadowPoint> points = groundLine(1.3f, 2.7f, 141);
  const TraceResult traced = tracer.trace(points, parseLight("spot:0,4,0:0,0,0:120:0.5"), {kSpp, 7, 2});
  EXPECT_EQ(traced.spp, kSpp);
  EXPECT_EQ(traced.rays, points.size() * kSpp);
  expectProfile(traced, points, [](double x) { return diskVisible(x, 0.5); });
}

TEST(ReferenceTracer, SunDiskPenumbraMatchesTheExactProfile) {
  const ShadowTracer tracer(test::squareOverPlane());
  const std::vector<ShadowPoint> points = groundLine(0.5f, 1.5f, 101);
  const TraceResult traced = tracer.trace(points, parseLight("dir:0,-1,0:10"), {kSpp, 7, 2});
  expectProfile(traced, points, [](double x) { return sunVisible(x, 10.0); });
}

TEST(ReferenceTracer, ExactLightsTraceOneRay) {
  const ShadowTracer tracer(test::squareOverPlane());
  const std::vector<ShadowPoint> points = groundLine(0.0f, 3.0f, 31);
  for (const char* light : {"spot:0,4,0:0,0,0:120", "dir:0,-1,0"}) {
    const TraceResult traced = tracer.trace(points, parseLight(light), {});
    EXPECT_EQ(traced.spp, 1) << light;
    const float edge = light[0] == 's' ? 2.0f : 1.0f;  // the point light's shadow is twice the occluder
    for (size_t i = 0; i < points.size(); ++i) {
      const float x = points[i].position.x;
      if (std::abs(x - edge) < 1e-3f) continue;
      EXPECT_EQ(traced.visibility[i], x < edge ? 0.0f : 1.0f) << light << " x = " << x;
    }
  }
}

TEST(ReferenceTracer, SameResultOnAnyThreadCountAndSeedMatters) {
  const ShadowTracer tracer(test::squareOverPlane());
  const std::vector<ShadowPoint> points = groundLine(1.5f, 2.5f, 300);
  const Light light = parseLight("spot:0,4,0:0,0,0:120:0.5");
  const TraceResult one = tracer.trace(points, light, {16, 3, 1}), three = tracer.trace(points, light, {16, 3, 3});
  EXPECT_EQ(one.visibility, three.visibility);
  EXPECT_EQ(one.standardError, three.standardError);
  EXPECT_NE(one.visibility, tracer.trace(points, light, {16, 4, 1}).visibility);
}

TEST(ReferenceTracer, SppMustBeFourSquares) {
  for (int spp : {4, 16, 36, 256, 1024, 16384}) EXPECT_EQ(SampleLayout::fromSpp(spp).spp(), spp);
  EXPECT_EQ(SampleLayout::fromSpp(1024).grid, 16);
  for (int spp : {0, -4, 1, 8, 17, 1000, 4 * 65 * 65}) EXPECT_THROW(SampleLayout::fromSpp(spp), std::invalid_argument);
}

TEST(ReferenceTracer, LightSamplesStayOnTheDiskAndInTheCone) {
  EXPECT_EQ(concentricDisk({0.5f, 0.5f}), glm::vec2(0.0f));
  const LightSampler disk(parseLight("spot:1,5,2:1,0,2:60:0.25"));
  const LightSampler sun(parseLight("dir:1,-2,0:5"));
  const glm::vec3 origin(0.0f);
  const float cosAlpha = std::cos(glm::radians(5.0f));
  int inner = 0;  // concentric map is area-preserving: a quarter of a uniform grid lands within radius 1/2
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      const glm::vec2 u((x + 0.5f) / 64.0f, (y + 0.5f) / 64.0f);
      inner += glm::length(concentricDisk(u)) < 0.5f;
      const glm::vec3 s = origin + disk.ray(origin, u).direction;
      EXPECT_NEAR(s.y, 5.0f, 1e-5f);
      EXPECT_LE(glm::length(glm::vec2(s.x - 1.0f, s.z - 2.0f)), 0.25f + 1e-6f);
      const ShadowRay r = sun.ray(origin, u);
      EXPECT_NEAR(glm::length(r.direction), 1.0f, 1e-5f);
      EXPECT_GE(glm::dot(r.direction, -glm::normalize(glm::vec3(1, -2, 0))), cosAlpha - 1e-6f);
    }
  EXPECT_NEAR(inner / 4096.0, 0.25, 0.01);
}

class Reference : public ClTest {};

TEST_F(Reference, PointLightHardEdgeLandsExactlyWhereGeometrySays) {
  const ReferenceResult r = renderReference(ctx(), test::squareOverPlane(), test::topDown(), test::pointAbove(), {});
  const Image& image = r.image;
  const auto &vis = image.require("visibility.Y").data, &err = image.require("stderr.Y").data,
             &px = image.require("P.X").data, &py = image.require("P.Y").data, &pz = image.require("P.Z").data,
             &a = image.require("A").data;
  constexpr float kEdgeBand = 1e-3f;  // world units: the ray offset (~7e-4 here) moves the edge by < 4e-4
  int shadowed = 0, lit = 0, occluder = 0;
  for (size_t i = 0; i < vis.size(); ++i) {
    EXPECT_EQ(err[i], 0.0f);
    if (a[i] == 0.0f) {
      EXPECT_EQ(vis[i], 1.0f) << "background";
      continue;
    }
    if (py[i] > 1.0f) {
      EXPECT_EQ(vis[i], 1.0f) << "the occluder's top shadows itself at " << px[i] << ", " << pz[i];
      ++occluder;
      continue;
    }
    const float edge = std::max(std::abs(px[i]), std::abs(pz[i])) - 2.0f;  // < 0 inside the shadow
    if (std::abs(edge) < kEdgeBand) continue;
    (edge < 0 ? shadowed : lit)++;
    EXPECT_EQ(vis[i], edge < 0 ? 0.0f : 1.0f) << "at " << px[i] << ", " << pz[i];
  }
  EXPECT_GT(shadowed, 2000);
  EXPECT_GT(lit, 5000);
  EXPECT_GT(occluder, 300);
  EXPECT_EQ(r.spp, 1);
  EXPECT_EQ(r.stderrMax, 0.0);
}

TEST_F(Reference, GBufferPixelsAreExactlyThoseOfRender) {
  const Scene scene = test::squareOverPlane();
  const Light light = parseLight("spot:0.5,4,0:0,0,0:120:0.3");
  const ReferenceResult ref = renderReference(ctx(), scene, test::topDown(), light, {16, 1, 0});
  const TechniqueInfo& sm = findTechnique("sm");
  Renderer renderer(ctx(), scene);
  const RenderResult ours = renderer.render(test::topDown(), light, sm, Params(sm.params));
  for (const char* channel : {"A", "P.X", "P.Y", "P.Z", "N.X", "N.Y", "N.Z", "depth.Z"})
    EXPECT_EQ(ref.image.require(channel).data, ours.image.require(channel).data) << channel;
  EXPECT_EQ(ref.image.attributes().at("penumbra:technique"), "reference");
  EXPECT_EQ(ref.image.numbers().at("penumbra:spp"), 16.0);  // statistics as numbers (EXR doubles)
  EXPECT_EQ(ref.image.numbers().at("penumbra:rays"), static_cast<double>(ref.rays));
  EXPECT_EQ(ref.image.numbers().at("penumbra:stderr-max"), ref.stderrMax);
}

// bench's peer keeps its rasterizer (ReferenceRaster) across frames: each frame equals a fresh reference bit for bit,
// also after a frame of another camera and size (the G-buffer's targets reallocated and reused).
TEST_F(Reference, AKeptRasterizerDrawsTheFramesAFreshOneDraws) {
  const Scene scene = test::squareOverPlane();
  const Light light = parseLight("spot:0.5,4,0:0,0,0:120:0.3");
  Camera small = test::topDown();
  small.width = 37, small.height = 29;
  const std::vector<Camera> cameras = {test::topDown(), small, test::topDown()};
  ReferenceRaster peer(ctx(), scene);
  for (size_t i = 0; i < cameras.size(); ++i) {
    const ReferenceResult kept = renderReference(peer, cameras[i], {light}, {16, 1, 0});
    const ReferenceResult fresh = renderReference(ctx(), scene, cameras[i], light, {16, 1, 0});
    ASSERT_EQ(kept.image.channelNames(), fresh.image.channelNames()) << i;
    for (const ImageChannel& channel : fresh.image.channels())
      EXPECT_EQ(kept.image.require(channel.name).data, channel.data) << i << " " << channel.name;
    EXPECT_EQ(kept.rays, fresh.rays) << i;
  }
}

TEST_F(Reference, NoNanAndVisibilityInRangeOnEveryBuiltinScene) {
  for (const ProceduralInfo& info : proceduralScenes()) {
    const Scene scene = makeProcedural(info.name);
    Camera camera = scene.cameras.empty() ? test::topDown() : scene.cameras.front();
    camera.width = 48;
    camera.height = 32;
    ASSERT_FALSE(scene.lights.empty()) << info.name;
    const ReferenceResult r = renderReference(ctx(), scene, camera, scene.lights.front(), {16, 1, 0});
    ASSERT_TRUE(test::saneImage(r.image, info.name));
  }
}

}  // namespace reference_tracer_test
}  // namespace penumbra::reference
