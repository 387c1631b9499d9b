// The rasterizer's checks against the naive reference rasterizer (tools/selftest/reference/raster_ref.h): random
// soups in every depth mode, perspective and orthographic, on viewports that are not multiples of a tile; soups through
// general projective (LiSPSM-like) matrices; watertight meshes (slivers, near-plane cuts); alpha-tested soups; the
// camera G-buffer against the analytic ray hits; a point light's six cube faces (90-degree views in distance depth) and
// the device's cube-face rule.
#include <fmt/format.h>

#include <glm/gtc/matrix_transform.hpp>
#include <optional>
#include <vector>

#include "host/cl/buffer.h"
#include "host/views/cube.h"
#include "host/views/raster_scene.h"
#include "raster/rasterizer.h"
#include "tools/selftest/reference/cube_ref.h"
#include "tools/selftest/reference/raster_compare.h"
#include "tools/selftest/selftest.h"

namespace penumbra::selftest {
namespace {

using test::RasterComparison;
using test::RasterOutput;

// The depth margin of a mode in ulps of the reference value (raster_compare.h: kViewZRel, kDistanceRel, kNdcAbs).
double depthUlps(DepthMode mode) {
  return mode == DepthMode::kNdc        ? test::kNdcAbs / test::kUlp
         : mode == DepthMode::kDistance ? test::kDistanceRel / test::kUlp
                                        : test::kViewZRel / test::kUlp;
}

// Coverage must be exact: a pixel with another triangle than the reference's is a mismatch unless it is a depth tie
// (at most `ties` of those) or an alpha test within rounding of its cutoff. The error reported is the worst depth.
void add(Measured& m, const RasterComparison& cmp, size_t ties, DepthMode mode, const std::string& label) {
  ref::Comparison c;
  c.count = cmp.covered;
  c.mismatches = cmp.mismatches + (cmp.ambiguous > ties ? cmp.ambiguous - ties : 0);
  c.worstError = cmp.worstUlps, c.worstAllowed = depthUlps(mode);
  c.report = cmp.report;
  if (cmp.ambiguous > ties) c.report += fmt::format("\n  {} depth ties, {} allowed", cmp.ambiguous, ties);
  m.comparison.merge(c, label);
  m.unit = "depth ulps";
}

// Draws `scene` through `view` into poisoned targets and compares the draw with the reference rasterizer's; with
// `alphaBorderTies`, the alpha-tested pixels within rounding of their cutoff may go either way too.
Measured drawAndCompare(Context& ctx, const Scene& scene, const RasterView& view, const std::string& label,
                        bool alphaBorderTies) {
  Rasterizer raster(ctx);
  uploadScene(raster, scene);
  const test::RasterOutput out = test::drawPoisoned(ctx, raster, view);
  const test::RefRasterizer reference(scene, view);
  const RasterComparison cmp = test::compareWithReference(out, reference, view, 10.0);
  Measured m;
  add(m, cmp, test::soupTiesAllowed(cmp.covered) + (alphaBorderTies ? test::borderPixels(reference) : 0),
      view.depthMode, label);
  return m;
}

Measured soup(Context& ctx, const test::SoupCase& c) {
  return drawAndCompare(ctx, test::triangleSoup(c.triangles, 1234 + c.width, 1.8f, c.size), test::soupView(c), c.name(),
                        false);
}

Measured masked(Context& ctx, const test::MaskedCase& c) {
  return drawAndCompare(ctx, test::maskedSoup(300, 77, c.filter), test::maskedView(c), c.name(), true);
}

// A point light's cube: a soup all around the light drawn through each face's 90-degree view in distance depth, the
// way a point light's shadow maps are drawn.
Measured cubeFaces(Context& ctx) {
  const glm::vec3 light(0.25f, -0.5f, 0.125f);
  const Scene scene = test::triangleSoup(600, 4242, 3.0f, 0.5f);
  Rasterizer raster(ctx);
  uploadScene(raster, scene);
  Measured m;
  for (int face = 0; face < CUBE_FACES; ++face) {
    RasterView view;
    view.view = glm::lookAt(light, light + cubeForward(face), cubeUp(face));
    view.projection = glm::perspective(glm::radians(90.0f), 1.0f, 0.05f, 20.0f);
    view.width = 67, view.height = 67, view.depthMode = DepthMode::kDistance;
    const test::RasterOutput out = test::drawPoisoned(ctx, raster, view);
    const test::RefRasterizer reference(scene, view);
    const RasterComparison cmp = test::compareWithReference(out, reference, view, 10.0);
    add(m, cmp, test::soupTiesAllowed(cmp.covered), view.depthMode, "face " + cubeFaceName(face));
  }
  return m;
}

// The device's face rule (cube_classify) against its definition, on adversarial and random directions: exact.
Measured cubeClassify(Context& ctx) {
  Measured m;
  for (const glm::vec3 light : {glm::vec3(0.0f), glm::vec3(0.75f, -2.5f, 10.0f)}) {
    std::vector<glm::vec3> directions = ref::adversarialDirections();
    for (const glm::vec3& v : ref::randomDirections(5000, 3)) directions.push_back(v);
    GBuffer g;
    g.width = static_cast<int>(directions.size()), g.height = 1;
    const std::vector<cl_float4> position = ref::positionsAround(light, directions);
    g.position = Buffer<cl_float4>(ctx, std::span<const cl_float4>(position));
    Buffer<int32_t> faces;
    classifyCubeFaces(ctx, g, light, faces);
    const std::vector<int32_t> device = faces.download(ctx), expected = ref::cubeClassify(position, light);
    m.comparison.merge(ref::compare(std::span<const int32_t>(device), std::span<const int32_t>(expected), {}),
                       fmt::format("light at {} {} {}", light.x, light.y, light.z));
  }
  m.unit = "face index";
  return m;
}

// A watertight mesh: every covered pixel centre covered once (the reference's count and the device's against the exact
// polygon), and its even and odd triangles drawn apart partition the whole draw.
void addWatertight(Measured& m, Context& ctx, const Scene& scene, const RasterView& view, const RasterOutput& out,
                   const test::RefRasterizer& reference, std::optional<size_t> expectedCovered) {
  std::string problems;
  if (test::worstCoverage(reference) > 1) problems += "\n  a pixel centre covered by two triangles of the mesh";
  if (expectedCovered && test::coveredPixels(out) != *expectedCovered)
    problems += fmt::format("\n  {} pixels covered, the polygon holds {}", test::coveredPixels(out), *expectedCovered);
  const test::HalvesPartition p = test::halvesPartition(ctx, scene, view, out);
  if (p.both != 0 || p.differ != 0)
    problems += fmt::format("\n  halves: {} pixels covered by both, {} differ from the whole", p.both, p.differ);
  if (!problems.empty()) m.comparison.mismatches += 1, m.comparison.report += problems;
}

// 720 slivers sharing every edge around one point.
Measured pinwheel(Context& ctx) {
  std::vector<glm::dvec2> rim;
  const Scene scene = test::pinwheelScene(rim);
  const RasterView view = test::pixelView(128, 64);
  Rasterizer raster(ctx);
  uploadScene(raster, scene);
  const RasterOutput out = test::drawPoisoned(ctx, raster, view);
  const test::RefRasterizer reference(scene, view);
  Measured m;
  add(m, test::compareWithReference(out, reference, view, 1.0), 0, view.depthMode, "pinwheel");
  addWatertight(m, ctx, scene, view, out, reference, test::samplesInside(rim, 128, 64));
  return m;
}

// A floor cut by the near plane, with and without back-face culling: no crack along the cuts.
Measured nearPlaneFloor(Context& ctx) {
  const Scene floor = test::nearPlaneFloor();
  Rasterizer raster(ctx);
  uploadScene(raster, floor);
  Measured m;
  for (bool cull : {false, true}) {
    const RasterView view = test::nearPlaneFloorView(cull);
    const RasterOutput out = test::drawPoisoned(ctx, raster, view);
    const test::RefRasterizer reference(floor, view);
    add(m, test::compareWithReference(out, reference, view, 100.0), 2, view.depthMode, cull ? "culled" : "both sides");
    if (raster.stats().trianglesSetUp != reference.drawnTriangles())
      m.comparison.mismatches += 1,
          m.comparison.report += fmt::format("\n  {} triangles set up, the reference draws {}",
                                             raster.stats().trianglesSetUp, reference.drawnTriangles());
    if (!cull) addWatertight(m, ctx, floor, view, out, reference, std::nullopt);
  }
  return m;
}

Measured gbuffer(Context& ctx, const RasterView& view, size_t minCovered) {
  const test::GBufferComparison g = test::compareGBuffer(ctx, test::twoSpheres(), view);
  Measured m;
  m.comparison.count = g.covered, m.comparison.mismatches = g.mismatches, m.comparison.report = g.report;
  m.comparison.worstError = g.worstPositionUlps, m.comparison.worstAllowed = test::kPositionUlps;
  if (g.covered <= minCovered)
    m.comparison.mismatches += 1, m.comparison.report += fmt::format("\n  {} pixels covered", g.covered);
  m.unit = "position ulps";
  return m;
}

}  // namespace

void addRasterChecks(std::vector<Check>& out) {
  for (const test::SoupCase& c : test::soupCases())
    out.push_back({"raster", "soup_" + c.name(), c.quick, [c](Context& ctx) { return soup(ctx, c); }});
  for (const test::ProjectiveCase& c : test::projectiveCases())
    out.push_back({"raster", "projective_" + c.name(), c.quick, [c](Context& ctx) {
                     Measured m =
                         drawAndCompare(ctx, test::projectiveSoup(c), test::projectiveView(c), c.name(), false);
                     if (m.comparison.count <= test::projectiveMinCovered(c))
                       m.comparison.mismatches += 1, m.comparison.report += "\n  the soup missed the view";
                     return m;
                   }});
  for (const test::MaskedCase& c : test::maskedCases())
    out.push_back({"raster", "alpha_" + c.name(), c.quick, [c](Context& ctx) { return masked(ctx, c); }});
  out.push_back({"raster", "watertight_pinwheel", true, pinwheel});
  out.push_back({"raster", "watertight_near_plane_floor", false, nearPlaneFloor});
  out.push_back({"raster", "gbuffer_perspective", true, [](Context& ctx) {
                   return gbuffer(ctx, test::gbufferPerspectiveView(), test::kGBufferPerspectiveCovered);
                 }});
  out.push_back({"raster", "gbuffer_ortho_scissor_distance", false, [](Context& ctx) {
                   return gbuffer(ctx, test::gbufferOrthoScissorView(), test::kGBufferOrthoCovered);
                 }});
  out.push_back({"raster", "cube_faces_distance", true, cubeFaces});
  out.push_back({"raster", "cube_classify", true, cubeClassify});
}

}  // namespace penumbra::selftest
