// The rasterizer's checks, shared by its tests (tests/raster_support.h adds the GoogleTest assertion) and `penumbra
// selftest`: procedural test scenes, views, a poisoned draw, and the one comparison against the reference rasterizer
// (exact coverage; depth within named tolerances; explicit rules for the only legitimate disagreements: depth ties
// between two triangles and fragments at the far plane).
#pragma once

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "host/cl/context.h"
#include "host/views/raster_scene.h"
#include "raster/rasterizer.h"
#include "tools/selftest/reference/inputs.h"
#include "tools/selftest/reference/raster_ref.h"

namespace penumbra::test {

inline constexpr double kUlp = 1.0 / (1 << 24);  // float unit roundoff at 1 (2^-24)
// Fine-stage view depth: float sums of positive terms e_k / w_k, one division, the float rounding of the clip
// matrix and per-vertex terms: measured <= 5 ulp, bound 16 ulp relative (raster/fine.cl).
inline constexpr double kViewZRel = 16 * kUlp;
// Distance = |origin + v dir| in float on top of the view depth: 8 more ulp.
inline constexpr double kDistanceRel = 24 * kUlp;
// NDC window depth from view depth: relative error of v times |d z_ndc / d ln v| <= 2, plus the float division.
inline constexpr double kNdcAbs = 48 * kUlp;
// Absolute floor for depths that cross zero (orthographic views with the near plane behind the eye): 8 ulp of
// the scene's depth range.
inline constexpr double kViewZAbsUlps = 8;
inline constexpr uint32_t kPoisonId = 0xdeadbeefu;  // the id poison (kPoison is the depth poison)

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
  targets.depth.fill(ctx, ref::kPoison);
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
        if (d != ref::kPoison || id != kPoisonId) fail(x, y, fmt::format("outside the scissor written: {} {}", id, d));
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

// The random-soup cases: viewports that are not multiples of a tile (1x1, odd, prime), every depth mode, perspective
// and orthographic views.
struct SoupCase {
  int width, height;
  bool orthographic;
  DepthMode mode;
  int triangles;
  float size;  // triangle size, world units (the view spans about 4)
  bool quick = false;
  std::string name() const {
    static const char* modes[] = {"Ndc", "ViewZ", "Distance"};
    return fmt::format("{}x{}_{}_{}_{}tris", width, height, orthographic ? "Ortho" : "Persp",
                       modes[static_cast<int>(mode)], triangles);
  }
};
inline std::vector<SoupCase> soupCases() {
  return {SoupCase{1, 1, false, DepthMode::kViewZ, 50, 2.0f},
          SoupCase{37, 19, false, DepthMode::kViewZ, 200, 0.6f},
          SoupCase{37, 19, true, DepthMode::kNdc, 200, 0.6f},
          SoupCase{131, 97, false, DepthMode::kDistance, 400, 0.4f, true},
          SoupCase{131, 97, true, DepthMode::kViewZ, 400, 0.4f, true},
          SoupCase{200, 130, false, DepthMode::kNdc, 600, 0.3f},
          SoupCase{257, 129, true, DepthMode::kDistance, 300, 0.5f},
          SoupCase{64, 256, false, DepthMode::kViewZ, 2000, 0.08f}};
}
inline RasterView soupView(const SoupCase& c) {
  if (c.orthographic)
    return orthoView(c.width, c.height, {0.5f, 1.0f, 6.0f}, {0, 0, 0}, {-2.2f, 2.0f, -1.9f, 2.1f}, 1.0f, 11.0f, c.mode);
  return perspectiveView(c.width, c.height, {0.5f, 1.0f, 6.0f}, {0, 0, 0}, 50.0f, 0.5f, 20.0f, c.mode);
}
// Random soups intersect: ties along intersection lines are legitimate, but rare.
inline size_t soupTiesAllowed(size_t covered) { return covered / 200 + 2; }

// Alpha-tested soups (raster/alpha.h): half the triangles of a random soup MASKed by a random texture.
// Adds a `size`^2 random alpha texture and a MASK material (cutoff 0.5) reading it; returns the material's index.
inline uint32_t addMaskMaterial(Scene& s, int size, int filter, int wrap, uint32_t seed, UvTransform transform = {}) {
  std::mt19937 rng(seed);
  const uint64_t offset = s.alphaTexels.size();
  for (int i = 0; i < size * size; ++i) s.alphaTexels.push_back(static_cast<uint8_t>(rng() & 0xff));
  s.alphaTextures.push_back({"random", static_cast<uint32_t>(size), static_cast<uint32_t>(size), offset});
  Material m;
  m.name = "mask";
  m.alphaMode = AlphaMode::kMask;
  m.alphaTexture = static_cast<int>(s.alphaTextures.size()) - 1;
  m.filter = filter, m.wrapS = m.wrapT = wrap;
  m.uvTransform = transform;
  s.materials.push_back(m);
  return static_cast<uint32_t>(s.materials.size()) - 1;
}

// Every other triangle of the soup alpha-tested, random texture coordinates in [-1, 2].
inline Scene maskedSoup(int count, uint32_t seed, int filter) {
  Scene s = triangleSoup(count, seed, 1.8f, 0.9f);
  s.materials = {plainMaterial()};
  const uint32_t mask = addMaskMaterial(s, 9, filter, ALPHA_WRAP_REPEAT, seed, {{0.1f, 0.2f}, 0.3f, {1.5f, 2.0f}});
  s.materialIds.resize(s.triangles.size());
  for (size_t t = 0; t < s.triangles.size(); ++t) s.materialIds[t] = t % 2 == 0 ? mask : 0;
  std::mt19937 rng(seed + 1);
  std::uniform_real_distribution<float> uv(-1.0f, 2.0f);
  for (size_t i = 0; i < s.positions.size(); ++i) s.uvs.emplace_back(uv(rng), uv(rng));
  return s;
}

inline size_t borderPixels(const RefRasterizer& ref) {
  size_t n = 0;
  for (uint8_t b : ref.result().alphaBorder) n += b;
  return n;
}

struct MaskedCase {
  bool orthographic;
  int filter;
  bool quick = false;
  std::string name() const {
    return std::string(orthographic ? "Ortho" : "Persp") + (filter == ALPHA_FILTER_LINEAR ? "Linear" : "Nearest");
  }
};
inline std::vector<MaskedCase> maskedCases() {
  return {MaskedCase{false, ALPHA_FILTER_LINEAR, true}, MaskedCase{false, ALPHA_FILTER_NEAREST},
          MaskedCase{true, ALPHA_FILTER_LINEAR}, MaskedCase{true, ALPHA_FILTER_NEAREST}};
}
inline RasterView maskedView(const MaskedCase& c) {
  return c.orthographic ? orthoView(97, 61, {0.5f, 1.0f, 6.0f}, {0, 0, 0}, {-2.2f, 2.0f, -1.9f, 2.1f}, 1.0f, 11.0f)
                        : perspectiveView(97, 61, {0.5f, 1.0f, 6.0f}, {0, 0, 0}, 50.0f, 0.5f, 20.0f);
}

// The camera G-buffer (Rasterizer::drawGBuffer): world position against the analytic ray-triangle hit computed in
// double, unit shading normals against the reference interpolation, facing sign, object ids, the same depth and ids as
// a depth-only draw, background and scissor rules. Float ray-plane intersection (raster/gbuffer.cl): error <=
// kPositionUlps ulp of (|eye| + |hit|) / |cos|, where cos is between the ray and the plane normal; measured worst
// about 2.
inline constexpr double kPositionUlps = 16;
inline constexpr double kUnitLength = 1e-5;   // |normal| - 1: one float normalisation
inline constexpr double kNormalError = 2e-4;  // interpolated normal vs double: float barycentrics of a float hit
inline constexpr double kMinCos = 0.05;       // grazing pixels skip the normal check: barycentrics there amplify error

// Allocates the G-buffer and fills it with poison, so that pixels the kernels never write show up.
inline GBuffer poisonedGBuffer(Context& ctx, int width, int height) {
  GBuffer g;
  const size_t n = static_cast<size_t>(width) * height;
  const cl_float4 poison{{ref::kPoison, ref::kPoison, ref::kPoison, ref::kPoison}};
  g.width = width, g.height = height;
  g.depth.allocate(ctx, n), g.depth.fill(ctx, ref::kPoison);
  g.triangleId.allocate(ctx, n), g.triangleId.fill(ctx, kPoisonId);
  g.objectId.allocate(ctx, n), g.objectId.fill(ctx, kPoisonId);
  g.position.allocate(ctx, n), g.position.fill(ctx, poison);
  g.normal.allocate(ctx, n), g.normal.fill(ctx, poison);
  return g;
}

struct GBufferComparison {
  size_t covered = 0, mismatches = 0;
  double worstPositionUlps = 0;
  std::string report;
};

inline GBufferComparison compareGBuffer(Context& ctx, const Scene& scene, const RasterView& view) {
  Rasterizer raster(ctx);
  uploadScene(raster, scene);
  GBuffer g = poisonedGBuffer(ctx, view.width, view.height);
  raster.drawGBuffer(view, g);
  const RasterOutput depthOnly = drawPoisoned(ctx, raster, view);
  const std::vector<uint32_t> ids = g.triangleId.download(ctx), objects = g.objectId.download(ctx);
  const std::vector<float> depth = g.depth.download(ctx);
  const std::vector<cl_float4> pos = g.position.download(ctx), nrm = g.normal.download(ctx);
  GBufferComparison c;
  auto fail = [&](int x, int y, const std::string& what) {
    if (++c.mismatches <= 8) c.report += fmt::format("\n  ({}, {}): {}", x, y, what);
  };
  if (ids != depthOnly.ids) fail(-1, -1, "triangle ids differ from a depth-only draw's");
  if (std::memcmp(depth.data(), depthOnly.depth.data(), depth.size() * sizeof(float)) != 0)
    fail(-1, -1, "depths differ from a depth-only draw's");
  const glm::dmat4 toWorld = glm::inverse(glm::dmat4(view.projection) * glm::dmat4(view.view));
  const glm::dvec3 eye = glm::inverse(glm::dmat4(view.view))[3];
  const Scissor s = view.scissor.value_or(Scissor{0, 0, view.width, view.height});
  for (int y = 0; y < view.height; ++y)
    for (int x = 0; x < view.width; ++x) {
      const size_t i = static_cast<size_t>(y) * view.width + x;
      const glm::dvec4 p(pos[i].s[0], pos[i].s[1], pos[i].s[2], pos[i].s[3]);
      const glm::dvec4 n(nrm[i].s[0], nrm[i].s[1], nrm[i].s[2], nrm[i].s[3]);
      if (x < s.x0 || x >= s.x1 || y < s.y0 || y >= s.y1) {
        if (!(p.x == ref::kPoison && n.w == ref::kPoison && objects[i] == kPoisonId))
          fail(x, y, "written outside the scissor");
        continue;
      }
      if (ids[i] == kNoTriangle) {
        if (!(p == glm::dvec4(0) && n == glm::dvec4(0) && objects[i] == kNoTriangle))
          fail(x, y, "background pixel not cleared");
        continue;
      }
      ++c.covered;
      if (ids[i] >= scene.triangles.size()) {
        fail(x, y, fmt::format("triangle id {}", ids[i]));
        continue;
      }
      if (objects[i] != scene.objectIds[ids[i]]) fail(x, y, fmt::format("object id {}", objects[i]));
      // The analytic hit of the pixel-centre ray with the triangle's plane, in double.
      const double xn = (2.0 * x + 1) / view.width - 1, yn = (2.0 * y + 1) / view.height - 1;
      glm::dvec4 a = toWorld * glm::dvec4(xn, yn, -1, 1), b = toWorld * glm::dvec4(xn, yn, 1, 1);
      a /= a.w, b /= b.w;
      const glm::dvec3 dir = glm::normalize(glm::dvec3(b - a));
      const glm::uvec3 tri = scene.triangles[ids[i]];
      const glm::dvec3 p0 = scene.positions[tri.x], p1 = scene.positions[tri.y], p2 = scene.positions[tri.z];
      const glm::dvec3 normal = glm::cross(p1 - p0, p2 - p0);
      const double cosine = std::abs(glm::dot(glm::normalize(normal), dir));
      const glm::dvec3 hit = glm::dvec3(a) + glm::dot(normal, p0 - glm::dvec3(a)) / glm::dot(normal, dir) * dir;
      const double scale = (glm::length(eye) + glm::length(hit)) / std::max(cosine, 1e-3) * kUlp;
      const double ulps = glm::length(glm::dvec3(p) - hit) / scale;
      c.worstPositionUlps = std::max(c.worstPositionUlps, ulps);
      if (!(ulps <= kPositionUlps)) fail(x, y, fmt::format("position {} ulps off, triangle {}", ulps, ids[i]));
      if (p.w != 1.0) fail(x, y, fmt::format("position w {}", p.w));
      if (!(std::abs(glm::length(glm::dvec3(n)) - 1.0) <= kUnitLength))
        fail(x, y, fmt::format("|normal| {}", glm::length(glm::dvec3(n))));
      if (n.w != (glm::dot(normal, dir) < 0 ? 1.0 : -1.0)) fail(x, y, fmt::format("facing sign {}", n.w));
      if (cosine < kMinCos) continue;
      glm::dvec3 w(glm::dot(normal, glm::cross(p1 - hit, p2 - hit)), glm::dot(normal, glm::cross(p2 - hit, p0 - hit)),
                   0);
      w /= glm::dot(normal, normal);
      w.z = 1 - w.x - w.y;
      w = glm::max(w, 0.0) / (glm::max(w, 0.0).x + glm::max(w, 0.0).y + glm::max(w, 0.0).z);
      const glm::dvec3 expected =
          glm::normalize(w.x * glm::dvec3(scene.normals[tri.x]) + w.y * glm::dvec3(scene.normals[tri.y]) +
                         w.z * glm::dvec3(scene.normals[tri.z]));
      const double error = glm::length(glm::dvec3(n) - expected);
      if (!(error <= kNormalError)) fail(x, y, fmt::format("normal {} off", error));
    }
  return c;
}

// Two spheres of different objects overlapping in view.
inline Scene twoSpheres() {
  Scene a = sphereScene(14, 24, 1.0f, {-0.6f, 0.1f, 0.0f}), b = sphereScene(10, 16, 0.7f, {0.9f, -0.2f, 0.8f});
  const uint32_t offset = static_cast<uint32_t>(a.positions.size());
  a.positions.insert(a.positions.end(), b.positions.begin(), b.positions.end());
  a.normals.insert(a.normals.end(), b.normals.begin(), b.normals.end());
  for (const glm::uvec3& t : b.triangles) a.triangles.push_back(t + offset);
  a.objectIds.resize(a.triangles.size(), 1);
  a.objectNames.push_back("second");
  return a;
}

// The G-buffer's views of twoSpheres(): perspective, and orthographic in distance depth through a scissor.
inline RasterView gbufferPerspectiveView() {
  return perspectiveView(113, 87, {0.8f, 1.6f, 4.5f}, {0, 0, 0}, 45.0f, 0.5f, 30.0f);
}
inline RasterView gbufferOrthoScissorView() {
  RasterView view =
      orthoView(90, 70, {-3, 2, 4}, {0, 0, 0}, {-2.2f, 2.2f, -1.7f, 1.7f}, 0.5f, 15.0f, DepthMode::kDistance);
  view.scissor = Scissor{7, 5, 83, 61};
  return view;
}
inline constexpr size_t kGBufferPerspectiveCovered = 2000, kGBufferOrthoCovered = 1500;  // at least

// General projective light matrices (raster/rasterizer.h: any invertible matrix for linear view depth, as a LiSPSM
// warp needs): random soups through a LiSPSM-like warp and a tilted perspective.
// LiSPSM-like: x_c, y_c and w_c from eye x and y only (w_c from the y axis, perpendicular to the view axis z),
// z_c from z and y. Rows over eye (x, y, z, 1); glm is column-major, so m[column][row].
inline glm::mat4 warpLike() {
  glm::mat4 m(0.0f);
  m[0][0] = 0.5f, m[1][0] = 0.1f;                   // x_c = 0.5 x + 0.1 y
  m[1][1] = 1.2f, m[3][1] = 0.3f;                   // y_c = 1.2 y + 0.3
  m[2][2] = 0.2f, m[1][2] = 0.05f, m[3][2] = 1.0f;  // z_c = 0.2 z + 0.05 y + 1
  m[1][3] = 0.3f, m[3][3] = 2.5f;                   // w_c = 0.3 y + 2.5
  return m;
}

// A perspective whose w also leans on x and y (a projective tilt after glm::perspective's).
inline glm::mat4 tiltedPerspective(float aspect) {
  glm::mat4 tilt(1.0f);
  tilt[0][3] = 0.05f, tilt[1][3] = 0.04f;
  return glm::perspective(glm::radians(50.0f), aspect, 0.5f, 20.0f) * tilt;
}

struct ProjectiveCase {
  int width, height;
  bool tilted;  // tiltedPerspective, else warpLike
  bool quick = false;
  std::string name() const { return fmt::format("{}x{}_{}", width, height, tilted ? "Tilted" : "WarpLike"); }
};
inline std::vector<ProjectiveCase> projectiveCases() {
  return {ProjectiveCase{37, 19, false}, ProjectiveCase{131, 97, false, true}, ProjectiveCase{256, 61, true},
          ProjectiveCase{97, 131, true, true}};
}
inline Scene projectiveSoup(const ProjectiveCase& c) { return triangleSoup(400, 4321 + c.width, 1.8f, 0.4f); }
inline RasterView projectiveView(const ProjectiveCase& c) {
  RasterView view;
  view.view = glm::lookAt(glm::vec3(0.5f, 1.0f, 6.0f), glm::vec3(0.0f), glm::vec3(0, 1, 0));
  view.projection = c.tilted ? tiltedPerspective(float(c.width) / float(c.height)) : warpLike();
  view.width = c.width, view.height = c.height, view.depthMode = DepthMode::kViewZ;
  return view;
}
// The soup must fill a twentieth of the view at least: otherwise the matrices missed it.
inline size_t projectiveMinCovered(const ProjectiveCase& c) { return static_cast<size_t>(c.width) * c.height / 20; }

// Watertightness (the top-left rule and the clipping paths): meshes sharing edges must cover every pixel centre of
// their union exactly once.

// World = window pixels: for power-of-two sizes x_win = x exactly for dyadic x, so snapping is exact and checks can
// place vertices on pixel centres (i + 0.5) and edges through them.
inline RasterView pixelView(int w, int h) {
  RasterView v;
  v.projection = glm::ortho(0.0f, float(w), 0.0f, float(h), -1.0f, 1.0f);
  v.width = w, v.height = h;
  return v;
}

// Pixel centres inside a convex counter-clockwise polygon of exactly representable window positions, with the same
// top-left rule: the set a watertight fan or mesh over that polygon must cover exactly once.
inline size_t samplesInside(const std::vector<glm::dvec2>& polygon, int w, int h) {
  size_t count = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      bool inside = true;
      for (size_t k = 0; k < polygon.size() && inside; ++k) {
        const glm::dvec2 a = polygon[k] * 256.0, b = polygon[(k + 1) % polygon.size()] * 256.0;
        const double e = (b.x - a.x) * (y * 256.0 + 128 - a.y) - (b.y - a.y) * (x * 256.0 + 128 - a.x);
        const bool owned = b.y < a.y || (b.y == a.y && b.x < a.x);
        inside = e > 0 || (e == 0 && owned);
      }
      count += inside;
    }
  return count;
}

inline size_t coveredPixels(const RasterOutput& out) {
  size_t n = 0;
  for (uint32_t id : out.ids) n += id != kNoTriangle;
  return n;
}

// The most triangles of the reference's draw covering one pixel centre (1 for a watertight mesh).
inline int worstCoverage(const RefRasterizer& ref) {
  int worst = 0;
  for (int c : ref.result().coverage) worst = std::max(worst, c);
  return worst;
}

// Draws the even and the odd triangles separately: pixels both halves cover, and pixels where their union differs
// from the whole draw (both 0 for a watertight rasterizer).
struct HalvesPartition {
  size_t both = 0, differ = 0;
};
inline HalvesPartition halvesPartition(Context& ctx, const Scene& scene, const RasterView& view,
                                       const RasterOutput& whole) {
  Scene halves[2] = {scene, scene};
  for (int h = 0; h < 2; ++h) {
    halves[h].triangles.clear();
    halves[h].objectIds.clear();
    for (size_t t = h; t < scene.triangles.size(); t += 2) halves[h].triangles.push_back(scene.triangles[t]);
    halves[h].objectIds.assign(halves[h].triangles.size(), 0);
  }
  Rasterizer raster(ctx);
  uploadScene(raster, halves[0]);
  const RasterOutput even = drawPoisoned(ctx, raster, view);
  uploadScene(raster, halves[1]);
  const RasterOutput odd = drawPoisoned(ctx, raster, view);
  HalvesPartition p;
  for (size_t i = 0; i < whole.ids.size(); ++i) {
    const bool a = even.ids[i] != kNoTriangle, b = odd.ids[i] != kNoTriangle;
    p.both += a && b;
    p.differ += (a || b) != (whole.ids[i] != kNoTriangle);
  }
  return p;
}

// `spokes` triangles from `centre` to a rim of radius `radius` whose points are rounded to the 1/256 grid (the
// polygon the fan must cover, into `rim`).
inline Scene fanScene(glm::vec2 centre, float radius, int spokes, std::vector<glm::dvec2>& rim) {
  std::vector<glm::vec3> p{{centre, 0}};
  rim.clear();
  for (int k = 0; k < spokes; ++k) {
    const float a = 2 * glm::pi<float>() * k / spokes;
    const glm::vec2 q = glm::round((centre + radius * glm::vec2(std::cos(a), std::sin(a))) * 256.0f) / 256.0f;
    p.emplace_back(q, 0);
    rim.emplace_back(q);
  }
  std::vector<glm::uvec3> t;
  for (int k = 0; k < spokes; ++k) t.emplace_back(0, 1 + k, 1 + (k + 1) % spokes);
  return makeScene(p, t);
}

// 720 wedges a fraction of a pixel wide at the centre: slivers sharing every edge, in pixelView(128, 64).
inline Scene pinwheelScene(std::vector<glm::dvec2>& rim) {
  return fanScene({40.0f + 37 / 256.0f, 33.0f + 91 / 256.0f}, 30.0f, 720, rim);
}

// A floor reaching far behind the camera of nearPlaneFloorView: many triangles cross the near plane and are cut in two.
inline Scene nearPlaneFloor() {
  Scene floor = gridScene(24, 24, {-60, -60}, {60, 60}, 0.0f, 0.0f, 1);
  for (glm::vec3& q : floor.positions) q = glm::vec3(q.x, 0.0f, -q.y);  // counter-clockwise seen from above
  return floor;
}
inline RasterView nearPlaneFloorView(bool cullBackFaces) {
  RasterView view = perspectiveView(101, 67, {0.3f, 1.0f, 0.2f}, {0.5f, 0.6f, -5.0f}, 70.0f, 0.25f, 100.0f);
  view.cullBackFaces = cullBackFaces;
  return view;
}

}  // namespace penumbra::test
