// Naive reference rasterizer: clip (near plane, guard band), snap, orient, then test every pixel centre of each
// triangle's box with exact 64-bit edge functions and the top-left rule; depth in double, perspective-correct
// from eye-space z carried through clipping; alpha-tested fragments kept only where their alpha reaches the cutoff;
// nearest wins, ties to the smaller triangle id.
#include "tools/selftest/reference/raster_ref.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "tools/selftest/reference/alpha_ref.h"

namespace penumbra::test {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kSubpixels = 256;          // 1/256-pixel snapping
constexpr double kCoordLimit = 1 << 29;  // subpixels

// The guard band factor: a power of two, 2^21 / 2^ceil(log2(size)).
double guardFactor(int size) {
  int log2 = 0;
  while ((1 << log2) < size) ++log2;
  return std::ldexp(1.0, 21 - log2);
}

// Clip coordinate r of float point p under the float matrix m, summed in the spec's order (products exact).
double clipRow(const glm::mat4& m, int r, const glm::vec3& p) {
  return ((double(m[0][r]) * double(p.x) + double(m[1][r]) * double(p.y)) + double(m[2][r]) * double(p.z)) +
         double(m[3][r]);
}

// The spec's separable form (raster/rasterizer.h): x_c from x and z, y_c from y and z, z_c and w_c from z only, and
// perspective (w_c = P23 z, P23 < 0) or orthographic (w_c = P33 > 0). Any other matrix is a general one: depth from
// z_eye carried through clipping as for every matrix, but no far plane.
bool separable(const glm::dmat4& P) {
  const bool form = P[1][0] == 0 && P[0][1] == 0 && P[0][2] == 0 && P[1][2] == 0 && P[0][3] == 0 && P[1][3] == 0 &&
                    P[0][0] != 0 && P[1][1] != 0;
  return form && ((P[2][3] < 0 && P[3][3] == 0 && P[3][2] != 0) || (P[2][3] == 0 && P[3][3] > 0 && P[2][2] != 0));
}

// E(a, b, p) > 0 when p is left of a -> b.
int64_t orient(int64_t ax, int64_t ay, int64_t bx, int64_t by, int64_t px, int64_t py) {
  return (bx - ax) * (py - ay) - (by - ay) * (px - ax);
}

}  // namespace

RefRasterizer::RefRasterizer(const Scene& scene, const RasterView& view) : view_(view) {
  const Scissor s = view.scissor.value_or(Scissor{0, 0, view.width, view.height});
  sx0_ = std::clamp(s.x0, 0, view.width), sx1_ = std::clamp(s.x1, 0, view.width);
  sy0_ = std::clamp(s.y0, 0, view.height), sy1_ = std::clamp(s.y1, 0, view.height);
  const glm::mat4 clip = rasterClipMatrix(view);
  const glm::dmat4 eye(view.view);
  byId_.resize(scene.triangles.size());
  materials_ = scene.materials, textures_ = scene.alphaTextures, texels_ = scene.alphaTexels;
  cull_.assign(scene.triangles.size(), view.cullBackFaces);
  if (scene.anyMayDiscard()) alpha_.resize(scene.triangles.size());
  for (uint32_t t = 0; t < scene.triangles.size(); ++t) {
    const Material* m = scene.materialOf(t);
    if (m != nullptr && view.cullSingleSided && !m->doubleSided) cull_[t] = true;
    Vertex v[3];
    bool finite = true;
    for (int k = 0; k < 3; ++k) {
      const glm::vec3 p = scene.positions[scene.triangles[t][k]];
      finite = finite && std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
      v[k] = {clipRow(clip, 0, p), clipRow(clip, 1, p), clipRow(clip, 2, p), clipRow(clip, 3, p),
              (eye * glm::dvec4(glm::dvec3(p), 1.0)).z};
    }
    if (m != nullptr && m->mayDiscard()) {
      AlphaTri& a = alpha_[t];
      a.material = static_cast<int>(scene.materialIds[t]);
      a.x = {v[0].x, v[1].x, v[2].x}, a.y = {v[0].y, v[1].y, v[2].y}, a.w = {v[0].w, v[1].w, v[2].w};
      double largest = 0;
      for (int k = 0; k < 3; ++k) {
        a.uv[k] = scene.uvs.empty() ? glm::dvec2(0.0) : glm::dvec2(scene.uvs[scene.triangles[t][k]]);
        largest = std::max({largest, std::abs(a.uv[k].x), std::abs(a.uv[k].y)});
      }
      a.slack = kUvSlack * (1 + largest);
    }
    if (finite) addTriangle(t, v);
  }
  RefRaster& r = result_;
  r.width = view.width, r.height = view.height;
  const size_t pixels = static_cast<size_t>(r.width) * r.height;
  r.triangleId.assign(pixels, kNoTriangle);
  r.viewZ.assign(pixels, kInf);
  r.depth.assign(pixels, kInf);
  r.coverage.assign(pixels, 0);
  r.alphaBorder.assign(pixels, 0);
  const glm::dmat4 P(view.projection);
  const bool farPlane = separable(P);
  for (const Tri& t : tris_)
    for (int y = t.y0; y <= t.y1; ++y)
      for (int x = t.x0; x <= t.x1; ++x) {
        const std::optional<double> z = viewZAt(t, x, y);
        if (!z) continue;
        const size_t i = r.index(x, y);
        ++r.coverage[i];
        const double zc = P[2][2] * -*z + P[3][2], wc = P[2][3] * -*z + P[3][3];
        if (farPlane && zc / wc > 1.0) continue;  // beyond the far plane
        bool border = false;
        const bool kept = alphaKeeps(t.id, x, y, &border);
        r.alphaBorder[i] |= border;
        if (!kept) continue;
        if (*z < r.viewZ[i] || (*z == r.viewZ[i] && t.id < r.triangleId[i])) r.viewZ[i] = *z, r.triangleId[i] = t.id;
      }
  for (int y = 0; y < r.height; ++y)
    for (int x = 0; x < r.width; ++x)
      if (r.triangleId[r.index(x, y)] != kNoTriangle) r.depth[r.index(x, y)] = depthOf(r.viewZ[r.index(x, y)], x, y);
}

// Sutherland-Hodgman against the near plane and the guard band, cutting each edge from its inside vertex; then
// a fan from the first polygon vertex.
void RefRasterizer::addTriangle(uint32_t id, const Vertex (&v)[3]) {
  const double gx = guardFactor(view_.width), gy = guardFactor(view_.height);
  auto distance = [&](const Vertex& p, int plane) {
    switch (plane) {
      case 0:
        return p.z + p.w;
      case 1:
        return p.x + gx * p.w;
      case 2:
        return gx * p.w - p.x;
      case 3:
        return p.y + gy * p.w;
      default:
        return gy * p.w - p.y;
    }
  };
  std::vector<Vertex> poly(v, v + 3);
  for (int plane = 0; plane < 5 && poly.size() >= 3; ++plane) {
    std::vector<Vertex> out;
    for (size_t i = 0; i < poly.size(); ++i) {
      const Vertex& p = poly[i];
      const Vertex& q = poly[(i + 1) % poly.size()];
      const double dp = distance(p, plane), dq = distance(q, plane);
      if (dp >= 0) out.push_back(p);
      if ((dp >= 0) == (dq >= 0)) continue;
      const Vertex& in = dp >= 0 ? p : q;
      const Vertex& outside = dp >= 0 ? q : p;
      const double din = dp >= 0 ? dp : dq, dout = dp >= 0 ? dq : dp;
      const double t = din / (din - dout);
      out.push_back({in.x + t * (outside.x - in.x), in.y + t * (outside.y - in.y), in.z + t * (outside.z - in.z),
                     in.w + t * (outside.w - in.w), in.eyeZ + t * (outside.eyeZ - in.eyeZ)});
    }
    poly = std::move(out);
  }
  fanned_ += poly.size() > 3;
  for (size_t k = 1; k + 1 < poly.size(); ++k) addSnapped(id, poly[0], poly[k], poly[k + 1]);
}

void RefRasterizer::addSnapped(uint32_t id, const Vertex& a, const Vertex& b, const Vertex& c) {
  if (!(a.w > 0 && b.w > 0 && c.w > 0)) return;
  Tri t{};
  t.id = id;
  const Vertex* v[3] = {&a, &b, &c};
  for (int k = 0; k < 3; ++k) {
    const double x = std::rint((v[k]->x / v[k]->w + 1.0) * (view_.width * (kSubpixels / 2.0)));
    const double y = std::rint((v[k]->y / v[k]->w + 1.0) * (view_.height * (kSubpixels / 2.0)));
    t.X[k] = static_cast<int64_t>(std::clamp(x, -kCoordLimit, kCoordLimit));
    t.Y[k] = static_cast<int64_t>(std::clamp(y, -kCoordLimit, kCoordLimit));
    t.w[k] = v[k]->w, t.eyeZ[k] = v[k]->eyeZ;
  }
  const int64_t area = orient(t.X[0], t.Y[0], t.X[1], t.Y[1], t.X[2], t.Y[2]);
  if (area == 0 || (cull_[id] && area < 0)) return;
  if (area < 0)
    std::swap(t.X[1], t.X[2]), std::swap(t.Y[1], t.Y[2]), std::swap(t.w[1], t.w[2]), std::swap(t.eyeZ[1], t.eyeZ[2]);
  const double minX = std::min({t.X[0], t.X[1], t.X[2]}), maxX = std::max({t.X[0], t.X[1], t.X[2]});
  const double minY = std::min({t.Y[0], t.Y[1], t.Y[2]}), maxY = std::max({t.Y[0], t.Y[1], t.Y[2]});
  t.x0 = std::max<int>(sx0_, static_cast<int>(std::ceil((minX - kSubpixels / 2) / kSubpixels)));
  t.x1 = std::min<int>(sx1_ - 1, static_cast<int>(std::floor((maxX - kSubpixels / 2) / kSubpixels)));
  t.y0 = std::max<int>(sy0_, static_cast<int>(std::ceil((minY - kSubpixels / 2) / kSubpixels)));
  t.y1 = std::min<int>(sy1_ - 1, static_cast<int>(std::floor((maxY - kSubpixels / 2) / kSubpixels)));
  if (t.x0 > t.x1 || t.y0 > t.y1) return;
  byId_[id].push_back(tris_.size());
  tris_.push_back(t);
}

// The pixel ray against the unsnapped triangle in homogeneous clip space: weights b with sum(b (x - xn w)) = 0 and
// sum(b (y - yn w)) = 0, clamped to the triangle.
bool RefRasterizer::alphaKeeps(uint32_t id, int x, int y, bool* border) const {
  if (alpha_.empty() || alpha_[id].material < 0) return true;
  const AlphaTri& a = alpha_[id];
  const double xn = (2.0 * x + 1.0) / view_.width - 1.0, yn = (2.0 * y + 1.0) / view_.height - 1.0;
  glm::dvec3 b = glm::cross(a.x - xn * a.w, a.y - yn * a.w);
  b = glm::max(b / (b.x + b.y + b.z), glm::dvec3(0.0));
  const double sum = b.x + b.y + b.z;
  b = sum > 0 && std::isfinite(sum) ? b / sum : glm::dvec3(1.0 / 3.0);
  const glm::dvec2 uv = b.x * a.uv[0] + b.y * a.uv[1] + b.z * a.uv[2];
  const Material& m = materials_[static_cast<size_t>(a.material)];
  const double coverage = ref::alphaCoverage(m, textures_, texels_, uv.x, uv.y), cutoff = ref::alphaCutoff(m);
  const bool keep = coverage >= cutoff;
  *border = std::abs(coverage - cutoff) < kAlphaBorder;
  for (const glm::dvec2 d : {glm::dvec2(a.slack, 0), glm::dvec2(-a.slack, 0), glm::dvec2(0, a.slack),
                             glm::dvec2(0, -a.slack)})
    *border = *border || (ref::alphaCoverage(m, textures_, texels_, uv.x + d.x, uv.y + d.y) >= cutoff) != keep;
  return keep;
}

std::optional<double> RefRasterizer::viewZAt(const Tri& t, int x, int y) const {
  const int64_t px = int64_t{x} * kSubpixels + kSubpixels / 2, py = int64_t{y} * kSubpixels + kSubpixels / 2;
  double weight[3];
  for (int k = 0; k < 3; ++k) {
    const int j = (k + 1) % 3;
    const int64_t e = orient(t.X[k], t.Y[k], t.X[j], t.Y[j], px, py);
    const bool owned = t.Y[j] < t.Y[k] || (t.Y[j] == t.Y[k] && t.X[j] < t.X[k]);  // left or top edge
    if (e < 0 || (e == 0 && !owned)) return std::nullopt;
    weight[(k + 2) % 3] = static_cast<double>(e);  // the vertex opposite edge k
  }
  double num = 0, den = 0;
  for (int k = 0; k < 3; ++k) num += weight[k] * -t.eyeZ[k] / t.w[k], den += weight[k] / t.w[k];
  return num / den;
}

std::optional<double> RefRasterizer::viewZOf(uint32_t id, int x, int y) const {
  if (id >= byId_.size()) return std::nullopt;
  for (size_t i : byId_[id])
    if (auto z = viewZAt(tris_[i], x, y)) return z;
  return std::nullopt;
}

// The stored depth: NDC depth or the distance to the eye point on the pixel's eye-space ray at view depth v.
double RefRasterizer::depthOf(double v, int x, int y) const {
  const glm::dmat4 P(view_.projection);
  switch (view_.depthMode) {
    case DepthMode::kViewZ:
      return v;
    case DepthMode::kNdc: {
      const glm::dvec4 c = P * glm::dvec4(0, 0, -v, 1);
      return 0.5 * c.z / c.w + 0.5;
    }
    case DepthMode::kDistance:
      break;
  }
  const glm::dmat4 inv = glm::inverse(P);
  const double xn = (2.0 * x + 1.0) / view_.width - 1.0, yn = (2.0 * y + 1.0) / view_.height - 1.0;
  glm::dvec4 a = inv * glm::dvec4(xn, yn, -1, 1), b = inv * glm::dvec4(xn, yn, 1, 1);
  a /= a.w, b /= b.w;
  const double s = (-v - a.z) / (b.z - a.z);
  return glm::length(glm::dvec3(a + s * (b - a)));
}

}  // namespace penumbra::test
