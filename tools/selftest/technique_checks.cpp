// The techniques' checks: every technique of the registry renders the square occluder over a plane
// (tools/selftest/reference/analytic_scenes.h) through the Renderer under a point-like spot light, and the pixels away
// from the hard edge must hold 0 or 1 within the technique's margin, as Techniques.HardEdge... holds PoCL to. The
// techniques that model an area light (pcss, vssm, izb) also render it under a disk light, against the exact
// visibility computed here in double: the share of the disk whose segment to the point crosses the square.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "host/scene/camera.h"
#include "host/techniques/izb_pattern.h"
#include "host/techniques/registry.h"
#include "tools/selftest/reference/analytic_scenes.h"
#include "tools/selftest/selftest.h"

namespace penumbra::selftest {
namespace {

// As Techniques.HardEdge...: a 1024 map over the 10x10 ground (0.014 per texel), and at least its counts of pixels
// checked on either side of the edge (test::kHardEdgeMinShadowed, kHardEdgeMinLit).
const test::Values kHardValues = {{"map-size", "1024"}};

constexpr float kOccluderY = 2.0f, kOccluderHalf = 1.0f;  // test::squareOverPlane()'s square: |x|, |z| < 1 at y = 2

// A NaN anywhere or a visibility outside [0, 1] (test::imageDefect) fails the check whatever the comparison says.
void requireSane(const Image& image, ref::Comparison& c) {
  const std::string defect = test::imageDefect(image);
  if (defect.empty()) return;
  ref::Comparison bad;
  bad.mismatches = 1, bad.worstError = INFINITY, bad.worstAllowed = c.worstAllowed;
  bad.report = "\n  " + defect;
  c.merge(bad, "the frame");
}

// Too few pixels of a kind to check: the scene or camera did not come out as the check assumes.
void requireAtLeast(ref::Comparison& c, const char* what, int count, int minimum) {
  if (count > minimum) return;
  c.mismatches += 1;
  c.report += fmt::format("\n  {} {} pixels, expected more than {}", count, what, minimum);
}

// Pixel i of the frame's image for a message: where it is and at which point of the ground.
std::string where(const Image& image, size_t i) {
  const size_t w = static_cast<size_t>(image.width());
  return fmt::format("({}, {}) at x = {:.4f}, z = {:.4f}", i % w, i / w, image.require("P.X").data[i],
                     image.require("P.Z").data[i]);
}

Measured hardEdge(Context& ctx, const std::string& technique) {
  const Scene scene = test::squareOverPlane();
  const RenderResult r = test::renderWith(ctx, scene, test::topDown(), test::pointAbove(), technique, kHardValues);
  const test::HardEdgeMargin margin = test::hardEdgeMargin(technique);
  const test::HardEdgeCount count = test::checkHardEdge(r.image, margin.band, margin.tolerance);
  ref::Comparison c;
  c.count = static_cast<size_t>(count.shadowed + count.lit);
  c.mismatches = static_cast<size_t>(count.wrong);
  c.worstError = count.worstError, c.worstAllowed = margin.tolerance;
  if (std::isfinite(count.worstError) && count.wrong != 0) c.worstFiniteError = count.worstError;
  const auto &vis = r.image.require("visibility.Y").data, &px = r.image.require("P.X").data,
             &pz = r.image.require("P.Z").data;
  for (size_t i : count.firstWrong) {
    const bool inside = std::max(std::abs(px[i]), std::abs(pz[i])) < 2.0f;  // the edge of checkHardEdge
    c.report += fmt::format("\n  {}: visibility {} vs expected {}", where(r.image, i), vis[i], inside ? 0 : 1);
  }
  requireAtLeast(c, "shadowed", count.shadowed, test::kHardEdgeMinShadowed);
  requireAtLeast(c, "lit", count.lit, test::kHardEdgeMinLit);
  requireSane(r.image, c);
  return {c, "visibility"};
}

// The area of the disk of radius `radius` about the origin inside the rectangle [x0, x1] x [y0, y1], exactly: the
// integral over x of the chord's overlap with [y0, y1], in pieces between the x where the circle crosses y0 or y1, on
// each of which the overlap is one of y1 - y0, h - y0, y1 + h, 2 h (h = sqrt(r^2 - x^2)) or empty, and
// int h dx = (x h + r^2 asin(x / r)) / 2.
double diskInRectangle(double radius, double x0, double x1, double y0, double y1) {
  const double lo = std::max(x0, -radius), hi = std::min(x1, radius);
  if (!(lo < hi) || !(y0 < y1)) return 0.0;
  const double r2 = radius * radius;
  auto chord = [&](double x) { return std::sqrt(std::max(0.0, r2 - x * x)); };
  auto chordIntegral = [&](double x) {
    return 0.5 * (x * chord(x) + r2 * std::asin(std::clamp(x / radius, -1.0, 1.0)));
  };
  std::vector<double> cuts = {lo, hi};
  for (double y : {y0, y1})
    if (std::abs(y) < radius)
      for (double x : {-chord(y), chord(y)})
        if (x > lo && x < hi) cuts.push_back(x);
  std::sort(cuts.begin(), cuts.end());
  double area = 0.0;
  for (size_t k = 0; k + 1 < cuts.size(); ++k) {
    const double a = cuts[k], b = cuts[k + 1], h = chord(0.5 * (a + b));
    if (!(b > a) || std::min(y1, h) <= std::max(y0, -h)) continue;
    const double top = y1 < h ? y1 * (b - a) : chordIntegral(b) - chordIntegral(a);
    const double bottom = y0 > -h ? y0 * (b - a) : -(chordIntegral(b) - chordIntegral(a));
    area += top - bottom;
  }
  return area;
}

// The light of the soft checks: pointAbove()'s spot made a horizontal disk of radius 0.5 at y = 4. The segment from a
// ground point p to a light point l crosses y = 2 halfway, so the square hides the light points with |l_x + p_x| < 2
// and |l_z + p_z| < 2: the penumbra is 2 r = 1 wide, the umbra |x|, |z| < 1.5.
constexpr double kDiskRadius = 0.5;
Light diskAbove() {
  Light light = test::pointAbove();
  light.radius = static_cast<float>(kDiskRadius);
  return light;
}

// The share of the disk light `light` (horizontal, at y = light.position.y above the occluder) that point p sees: the
// segments through the square at y = 2 reach the light's plane in a rectangle, where t = (2 - p_y) / (l_y - p_y) is
// the fraction of the way at which they cross it.
double exactVisibility(const Light& light, const glm::dvec3& p) {
  const glm::dvec3 c(light.position);
  const double t = (kOccluderY - p.y) / (c.y - p.y);
  if (!(t > 0.0 && t < 1.0)) return 1.0;
  // |p (1 - t) + t l| < half along x and z, in coordinates about the light's centre.
  auto range = [&](double pc, double cc, double& lo, double& hi) {
    lo = (-kOccluderHalf - pc * (1.0 - t)) / t - cc, hi = (kOccluderHalf - pc * (1.0 - t)) / t - cc;
  };
  double x0, x1, z0, z1;
  range(p.x, c.x, x0, x1);
  range(p.z, c.z, z0, z1);
  const double r = light.radius;
  return 1.0 - diskInRectangle(r, x0, x1, z0, z1) / (std::numbers::pi * r * r);
}

// izb's answer for its own N points (host/techniques/izb_pattern.h, as kernels/izb.cl izb_soft_test turns them for
// the pixel with G-buffer index `key`): the share of them whose segment to p misses the square.
double patternVisibility(const Light& light, const IzbLightPattern& pattern, uint32_t key, const glm::dvec3& p) {
  // The disk's frame as izb's describeLight sets it up.
  const glm::vec3 axis = light.axis(), tangent = glm::normalize(glm::cross(axis, chooseUp(axis)));
  const glm::vec3 bitangent = glm::cross(axis, tangent);
  int seen = 0;
  for (int j = 0; j < pattern.count(); ++j) {
    const glm::vec2 u = pattern.point(key, j);
    const glm::dvec3 l = glm::dvec3(light.position + light.radius * (u.x * tangent + u.y * bitangent));
    const double t = (kOccluderY - p.y) / (l.y - p.y);
    const glm::dvec3 q = p + t * (l - p);
    seen += !(t > 0.0 && t < 1.0 && std::abs(q.x) < kOccluderHalf && std::abs(q.z) < kOccluderHalf);
  }
  return double(seen) / pattern.count();
}

// izb's light points per sample in the soft check (its default, docs/techniques/izb.md).
constexpr int kIzbLightGrid = 8;
// izb is exact for its N points (docs/techniques/izb.md), so its error against the exact share is the sampling error
// of those points, mean |patternVisibility - exactVisibility|, computed here for the same pixels; on top of it the
// rays that pass within rounding of the square's edges: tests/izb_test.cpp lets one ray in 10^4 differ from the
// reference traced through the same points, which moves a pixel by 1/N per ray and the mean |error| by at most 10^-4.
constexpr double kIzbRayShare = 1e-4;

struct SoftCase {
  std::string technique;
  test::Values values;
  // The mean |visibility - exact| over the ground pixels allowed; 0: izb's (kIzbRayShare above its points' own).
  double margin;
};

// The margins are about 2.5 times what PoCL gives (pthread, 2-core AMD EPYC, map size 1024, the 160x120 view; the
// filters' own error on a penumbra 1 wide, 0.0035 and 0.0028 of mean |error|), so that another device's rounding
// passes and a penumbra of the wrong width (a hard edge here would give ~0.05) does not.
const std::vector<SoftCase>& softCases() {
  static const std::vector<SoftCase> kCases = {
      {"pcss", {{"map-size", "1024"}}, 0.008},  // measured 0.00351: its Poisson PCF against the disk
      {"vssm", {{"map-size", "1024"}}, 0.007},  // measured 0.00278: its box filters against the disk
      {"izb", {{"map-size", "1024"}, {"izb-light-samples", std::to_string(kIzbLightGrid * kIzbLightGrid)}}, 0.0},
  };
  return kCases;
}

// Enough umbra, penumbra and lit ground pixels for the mean error to mean something: about half of what the 160x120
// view of the 0.5 disk holds (1658, 3466 and 10690 of 15814 ground pixels).
constexpr int kMinUmbra = 800, kMinPenumbra = 1700, kMinSoftLit = 5000;

Measured softShadow(Context& ctx, const SoftCase& sc) {
  const Scene scene = test::squareOverPlane();
  const Camera camera = test::topDown();
  const Light light = diskAbove();
  const RenderResult r = test::renderWith(ctx, scene, camera, light, sc.technique, sc.values);
  const Image& image = r.image;
  const auto &vis = image.require("visibility.Y").data, &px = image.require("P.X").data,
             &py = image.require("P.Y").data, &pz = image.require("P.Z").data, &a = image.require("A").data;
  const bool izb = sc.technique == "izb";
  const IzbLightPattern pattern(kIzbLightGrid);
  const size_t width = static_cast<size_t>(image.width()), height = static_cast<size_t>(image.height());
  double sum = 0.0, patternSum = 0.0, worst = -1.0;
  size_t worstPixel = 0, ground = 0;
  int umbra = 0, penumbra = 0, lit = 0;
  for (size_t i = 0; i < vis.size(); ++i) {
    if (a[i] == 0.0f || py[i] > 0.5f) continue;  // background, or the occluder itself (as test::checkHardEdge)
    const glm::dvec3 p(px[i], py[i], pz[i]);
    const double exact = exactVisibility(light, p), error = std::abs(double(vis[i]) - exact);
    ++ground, sum += error;
    (exact < 1e-9 ? umbra : exact > 1.0 - 1e-9 ? lit : penumbra)++;
    if (!(error <= worst)) worst = error, worstPixel = i;
    if (izb) {  // the G-buffer's rows are bottom-up: izb keys its pattern by that index
      const size_t row = i / width, column = i % width;
      const auto key = static_cast<uint32_t>((height - 1 - row) * width + column);
      patternSum += std::abs(patternVisibility(light, pattern, key, p) - exact);
    }
  }
  ref::Comparison c;
  c.count = ground;
  const double n = double(std::max<size_t>(ground, 1));
  c.worstError = sum / n;
  c.worstAllowed = izb ? patternSum / n + kIzbRayShare : sc.margin;
  if (std::isnan(c.worstError) || !(c.worstError <= c.worstAllowed)) {
    c.mismatches = 1, c.worstFiniteError = std::isfinite(c.worstError) ? c.worstError : 0.0;
    c.report = fmt::format("\n  mean |visibility - exact| over {} ground pixels {:.6f}, margin {:.6f}", ground,
                           c.worstError, c.worstAllowed);
  }
  if (ground != 0)
    c.report += fmt::format("\n  worst pixel {}: visibility {} vs exact {:.6f}", where(image, worstPixel),
                            vis[worstPixel], exactVisibility(light, {px[worstPixel], py[worstPixel], pz[worstPixel]}));
  requireAtLeast(c, "umbra", umbra, kMinUmbra);
  requireAtLeast(c, "penumbra", penumbra, kMinPenumbra);
  requireAtLeast(c, "lit", lit, kMinSoftLit);
  requireSane(image, c);
  return {c, "visibility (mean |error|)"};
}

}  // namespace

void addTechniqueChecks(std::vector<Check>& out) {
  for (const TechniqueInfo& info : techniques())
    out.push_back({"technique", info.name + "_square_point", true,
                   [name = info.name](Context& ctx) { return hardEdge(ctx, name); }});
  for (const SoftCase& sc : softCases())
    out.push_back(
        {"technique", sc.technique + "_square_disk", true, [sc](Context& ctx) { return softShadow(ctx, sc); }});
}

}  // namespace penumbra::selftest
