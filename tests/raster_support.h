// Shared pieces of the rasterizer tests: procedural test scenes, views, a poisoned draw, and the one comparison
// against the reference rasterizer (exact coverage; depth within named tolerances; explicit rules for the only
// legitimate disagreements: depth ties between two triangles and fragments at the far plane).
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "host/cl/context.h"
#include "raster/rasterizer.h"
#include "tests/reference/raster_ref.h"
#include "tests/support/cl_test.h"

namespace penumbra::test {

constexpr double kUlp = 1.0 / (1 << 24);  // float unit roundoff at 1 (2^-24)
// Fine-stage view depth: float sums of positive terms e_k / w_k, one division, the float rounding of the clip
// matrix and per-vertex terms: measured <= 5 ulp, bound 16 ulp relative (raster/fine.cl).
constexpr double kViewZRel = 16 * kUlp;
// Distance = |origin + v dir| in float on top of the view depth: 8 more ulp.
constexpr double kDistanceRel = 24 * kUlp;
// NDC window depth from view depth: relative error of v times |d z_ndc / d ln v| <= 2, plus the float division.
constexpr double kNdcAbs = 48 * kUlp;
// Absolute floor for depths that cross zero (orthographic views with the near plane behind the eye): 8 ulp of
// the scene's depth range.
constexpr double kViewZAbsUlps = 8;
constexpr uint32_t kPoisonId = 0xdeadbeefu;  // the id poison (kPoison is the depth poison)

inline Scene makeScene(std::vector<glm::vec3> positions, std::vector<glm::uvec3> triangles) {
  Scene s;
  s.positions = std::move(positions);
  s.triangles = std::move(triangles);
  s.normals.assign(s.positions.size(), glm::vec3(0, 0, 1));
  s.objectIds.assign(s.triangles.size(), 0);
  s.objectNames = {"test"};
  return s;
}

// `count` random triangles of up to `size` across, centred in the cube [-extent, extent]^3.
inline Scene triangleSoup(int count, uint32_t seed, float extent, float size) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> centre(-extent, extent), offset(-size, size);
  std::vector<glm::vec3> p;
  std::vector<glm::uvec3> t;
  for (int i = 0; i < count; ++i) {
    const glm::vec3 c(centre(rng), centre(rng), centre(rng));
    for (int k = 0; k < 3; ++k) p.push_back(c + glm::vec3(offset(rng), offset(rng), offset(rng)));
    t.emplace_back(3 * i, 3 * i + 1, 3 * i + 2);
  }
  return makeScene(std::move(p), std::move(t));
}

// A closed UV sphere with outward unit normals and counter-clockwise (outside) faces.
inline Scene sphereScene(int stacks, int slices, float radius, glm::vec3 centre) {
  std::vector<glm::vec3> p, n;
  for (int i = 0; i <= stacks; ++i)
    for (int j = 0; j <= slices; ++j) {
      const float theta = glm::pi<float>() * i / stacks, phi = 2 * glm::pi<float>() * j / slices;
      const glm::vec3 d(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
      p.push_back(centre + radius * d);
      n.push_back(d);
    }
  std::vector<glm::uvec3> t;
  for (int i = 0; i < stacks; ++i)
    for (int j = 0; j < slices; ++j) {
      const uint32_t a = i * (slices + 1) + j, b = a + slices + 1;
      if (i != 0) t.emplace_back(a, a + 1, b);
      if (i + 1 != stacks) t.emplace_back(a + 1, b + 1, b);
    }
  Scene s = makeScene(std::move(p), std::move(t));
  s.normals = std::move(n);
  return s;
}

// A regular grid of nx * ny quads (two triangles each) over [x0, x1] x [y0, y1] at height z, interior vertices
// moved by up to `jitter` cells (a dyadic step, so orthographic snapping is exact), counter-clockwise seen from +z.
inline Scene gridScene(int nx, int ny, glm::vec2 lo, glm::vec2 hi, float z, float jitter, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> step(-64, 64);
  std::vector<glm::vec3> p;
  const glm::vec2 cell = (hi - lo) / glm::vec2(nx, ny);
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      glm::vec2 q = lo + cell * glm::vec2(i, j);
      if (i != 0 && i != nx) q.x += jitter * cell.x * step(rng) / 128.0f;
      if (j != 0 && j != ny) q.y += jitter * cell.y * step(rng) / 128.0f;
      p.emplace_back(q, z);
    }
  std::vector<glm::uvec3> t;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const uint32_t a = j * (nx + 1) + i, b = a + 1, c = a + nx + 1, d = c + 1;
      if ((i + j) % 2 == 0)
        t.emplace_back(a, b, d), t.emplace_back(a, d, c);
      else
        t.emplace_back(a, b, c), t.emplace_back(b, d, c);
    }
  return makeScene(std::move(p), std::move(t));
}

inline RasterView perspectiveView(int w, int h, glm::vec3 eye, glm::vec3 target, float fovDeg, float zNear, float zFar,
                                  DepthMode mode = DepthMode::kViewZ) {
  RasterView v;
  v.view = glm::lookAt(eye, target, glm::vec3(0, 1, 0));
  v.projection = glm::perspective(glm::radians(fovDeg), float(w) / float(h), zNear, zFar);
  v.width = w, v.height = h, v.depthMode = mode;
  return v;
}

inline RasterView orthoView(int w, int h, glm::vec3 eye, glm::vec3 target, glm::vec4 box, float zNear, float zFar,
                            DepthMode mode = DepthMode::kViewZ) {
  RasterView v;
  v.view = glm::lookAt(eye, target, glm::vec3(0, 1, 0));
  v.projection = glm::ortho(box.x, box.y, box.z, box.w, zNear, zFar);
  v.width = w, v.height = h, v.depthMode = mode;
  return v;
}

struct RasterOutput {
  std::vector<float> depth;
  std::vector<uint32_t> ids;
};

// Draws into targets filled with poison first (pixels outside a scissor must keep it).
inline RasterOutput drawPoisoned(Context& ctx, Rasterizer& raster, const RasterView& view) {
  RasterTargets targets;
  const size_t pixels = static_cast<size_t>(view.width) * view.height;
  targets.depth.allocate(ctx, pixels);
  targets.triangleId.allocate(ctx, pixels);
  targets.depth.fill(ctx, kPoison);
  targets.triangleId.fill(ctx, kPoisonId);
  raster.draw(view, targets);
  return {targets.depth.download(ctx), targets.triangleId.download(ctx)};
}

struct RasterComparison {
  size_t covered = 0;    // pixels the reference covers
  size_t ambiguous = 0;  // different ids, but a depth tie (or a fragment at the far plane) within tolerance
  size_t mismatches = 0;
  double worstUlps = 0;  // largest depth error of matching pixels, in ulps of the reference value
  std::string report;
};

// Compares a draw with the reference: ids exactly (except ties), depths within the mode's tolerance, untouched
// poison outside the scissor. `depthScale`: the scene's largest |view depth| (absolute floor of the tolerance).
inline RasterComparison compareWithReference(const RasterOutput& out, const RefRasterizer& ref, const RasterView& view,
                                             double depthScale) {
  const RefRaster& r = ref.result();
  const Scissor s = view.scissor.value_or(Scissor{0, 0, view.width, view.height});
  const double viewAbs = kViewZAbsUlps * kUlp * depthScale;
  RasterComparison c;
  auto fail = [&](int x, int y, const std::string& what) {
    if (++c.mismatches <= 8) c.report += fmt::format("\n  ({}, {}): {}", x, y, what);
  };
  auto depthTol = [&](double e) {
    switch (view.depthMode) {
      case DepthMode::kNdc:
        return kNdcAbs;
      case DepthMode::kViewZ:
        return kViewZRel * std::abs(e) + viewAbs;
      case DepthMode::kDistance:
        break;
    }
    return kDistanceRel * std::abs(e) + viewAbs;
  };
  const double farViewZ = [&] {  // where z_ndc = 1, for the far-plane rule
    const glm::dmat4 P(view.projection);
    if (P[0][3] != 0 || P[1][3] != 0) return std::numeric_limits<double>::infinity();  // general: no far plane
    return P[2][3] != 0 ? P[3][2] / (P[2][2] - P[2][3]) : (P[3][2] - P[3][3]) / P[2][2];
  }();
  for (int y = 0; y < view.height; ++y)
    for (int x = 0; x < view.width; ++x) {
      const size_t i = r.index(x, y);
      const float d = out.depth[i];
      const uint32_t id = out.ids[i];
      if (x < s.x0 || x >= s.x1 || y < s.y0 || y >= s.y1) {
        if (d != kPoison || id != kPoisonId) fail(x, y, fmt::format("outside the scissor written: {} {}", id, d));
        continue;
      }
      const uint32_t want = r.triangleId[i];
      c.covered += want != kNoTriangle;
      if (id == want) {
        const double e = r.depth[i], err = std::abs(double(d) - e);
        if (want == kNoTriangle ? !(std::isinf(d) && d > 0) : !(err <= depthTol(e)))
          fail(x, y, fmt::format("triangle {} depth {} vs reference {}", id, d, e));
        else if (want != kNoTriangle && e != 0)
          c.worstUlps = std::max(c.worstUlps, err / std::abs(e) / kUlp);
        continue;
      }
      const std::optional<double> mine = id == kNoTriangle ? std::nullopt : ref.viewZOf(id, x, y);
      const double tieTol = 2 * (kViewZRel * std::abs(r.viewZ[i]) + viewAbs);
      const bool tie = mine && want != kNoTriangle && std::abs(*mine - r.viewZ[i]) <= tieTol;
      const bool atFar = (want == kNoTriangle && mine && std::abs(*mine - farViewZ) <= tieTol) ||
                         (id == kNoTriangle && std::abs(r.viewZ[i] - farViewZ) <= tieTol);
      if (tie || atFar || r.alphaBorder[i])
        ++c.ambiguous;
      else
        fail(x, y, fmt::format("triangle {} (depth {}) vs reference {} (view depth {})", id, d, want, r.viewZ[i]));
    }
  return c;
}

// Expects no mismatches and at most `maxAmbiguous` ties.
inline ::testing::AssertionResult matchesReference(const RasterComparison& c, size_t maxAmbiguous = 0) {
  if (c.mismatches == 0 && c.ambiguous <= maxAmbiguous) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << c.mismatches << " mismatching pixels, " << c.ambiguous
                                       << " depth ties (allowed " << maxAmbiguous << "), " << c.covered << " covered"
                                       << c.report;
}

}  // namespace penumbra::test
