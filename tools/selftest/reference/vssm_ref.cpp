// VSSM reference: the per-pixel algorithm in double precision, naively (see vssm_ref.h).
#include "tools/selftest/reference/vssm_ref.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>
#include <vector>

#include "tools/selftest/reference/moments_ref.h"
#include "tools/selftest/reference/pyramid_ref.h"

namespace penumbra::ref {

struct VssmReference::Rx {
  double u, v, depth, bias, biasSlope, t, tSlope;
  uint32_t seed;
};

// Algorithm 2's sums.
struct VssmReference::Sums {
  double m1 = 0, m2 = 0, vsmArea = 0, shift = 0, litArea = 0, pcfArea = 0, pcfBlocked = 0, pcfDepth = 0;
  int visited = 0;
};

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

double hash01(uint32_t x) {  // Wellons' lowbias32, top 24 bits
  x ^= x >> 16;
  x *= 0x7feb352du;
  x ^= x >> 15;
  x *= 0x846ca68bu;
  x ^= x >> 16;
  return double(x >> 8) / 16777216.0;
}

// Eq. 4 with z_unocc = t, directly: (z_Avg - P t) / (1 - P), P from eq. 1.
double occluderDepth(double mean, double variance, double t) {
  const double p = variance / (variance + (t - mean) * (t - mean));
  return (mean - p * t) / (1.0 - p);
}

double chebyshev(double mean, double variance, double t) {
  if (!(t > mean)) return 1.0;
  return variance / (variance + (t - mean) * (t - mean));
}

// Texels of a pyramid level `level` texels across covering base interval [a, b] of `base` texels (pyramid.h
// pyramid_cover_span, widened by 1e-3 level texels against rounding).
std::pair<int, int> span(double a, double b, uint32_t base, uint32_t level) {
  const double s = double(level) / base;
  return {std::max(int(std::floor(a * s - 1e-3)), 0), std::min(int(std::floor(b * s + 1e-3)), int(level) - 1)};
}

}  // namespace

VssmReference::VssmReference(const std::vector<float>& depth, uint32_t width, uint32_t height, const VssmLight& light,
                             const VssmSettings& settings)
    : depth_(depth), width_(width), height_(height), light_(light), settings_(settings) {
  std::vector<float> normalized(depth.size());
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x)
      normalized[y * width + x] = static_cast<float>(normalizeDepth(depth[y * width + x], light.zNear, light.zFar));
  const uint32_t f = static_cast<uint32_t>(settings.satReduce);
  satWidth_ = (width + f - 1) / f, satHeight_ = (height + f - 1) / f;
  const size_t pitch = satWidth_ + 1;
  for (int c = 0; c < 2; ++c) sat_[c].assign(pitch * (satHeight_ + 1), 0.0);
  for (uint32_t y = 0; y < satHeight_; ++y)
    for (uint32_t x = 0; x < satWidth_; ++x) {
      double value[2] = {0, 0};
      for (uint32_t j = y * f; j < (y + 1) * f; ++j)
        for (uint32_t i = x * f; i < (x + 1) * f; ++i) {
          const double z = i < width && j < height ? normalized[j * width + i] : 1.0;
          value[0] += z / (f * f), value[1] += z * z / (f * f);
        }
      for (int c = 0; c < 2; ++c) {
        std::vector<double>& s = sat_[c];
        s[(y + 1) * pitch + x + 1] = value[c] + s[y * pitch + x + 1] + s[(y + 1) * pitch + x] - s[y * pitch + x];
      }
    }
  hsm_ = minMaxPyramid(normalized, width, height);
  for (uint32_t w = width, h = height;; w = std::max(1u, w / 2), h = std::max(1u, h / 2)) {
    hsmSizes_.emplace_back(w, h);
    if (w == 1 && h == 1) break;
  }
}

// The integral of channel c over [0, u] x [0, v] (block units): bilinear between the integer corners of the prefix
// sums.
double VssmReference::corner(double u, double v, int c) const {
  const int i = std::min(int(std::floor(u)), int(satWidth_)), j = std::min(int(std::floor(v)), int(satHeight_));
  const double fu = u - i, fv = v - j;
  const int i1 = std::min(i + 1, int(satWidth_)), j1 = std::min(j + 1, int(satHeight_));
  auto s = [&](int a, int b) { return sat_[c][size_t(b) * (satWidth_ + 1) + a]; };
  return (1 - fv) * ((1 - fu) * s(i, j) + fu * s(i1, j)) + fv * ((1 - fu) * s(i, j1) + fu * s(i1, j1));
}

// Mean (z, z^2) over the box; outside the map counts as depth 1 (no occluder).
std::pair<double, double> VssmReference::boxMoments(double lx, double ly, double hx, double hy) const {
  const double ax = std::clamp(lx, 0.0, double(width_)), bx = std::clamp(hx, ax, double(width_));
  const double ay = std::clamp(ly, 0.0, double(height_)), by = std::clamp(hy, ay, double(height_));
  const double area = (hx - lx) * (hy - ly), outside = area - (bx - ax) * (by - ay);
  const double f = settings_.satReduce;
  double sum[2];
  for (int c = 0; c < 2; ++c)
    sum[c] = (corner(bx / f, by / f, c) - corner(ax / f, by / f, c) - corner(bx / f, ay / f, c) +
              corner(ax / f, ay / f, c)) *
                 f * f +
             outside;
  return {sum[0] / area, sum[1] / area};
}

// vssm.cl pyramid_cover_level: the finest HSM level (0: the map) whose texels over [ax, bx] x [ay, by] span at most
// most + 1 a side, or the coarsest; their spans in sx and sy.
size_t VssmReference::coverLevel(double ax, double bx, double ay, double by, int most, std::pair<int, int>& sx,
                                 std::pair<int, int>& sy) const {
  size_t l = 0;
  sx = span(ax, bx, width_, width_), sy = span(ay, by, height_, height_);
  while ((sx.second - sx.first > most || sy.second - sy.first > most) && l + 1 < hsm_.size()) {
    ++l;
    sx = span(ax, bx, width_, hsmSizes_[l].first), sy = span(ay, by, height_, hsmSizes_[l].second);
  }
  return l;
}

std::pair<double, double> VssmReference::hsmRange(double lx, double ly, double hx, double hy) const {
  double lo = kInf, hi = -kInf;
  if (lx < 0 || ly < 0 || hx > width_ || hy > height_) lo = hi = 1.0;
  const double ax = std::clamp(lx, 0.0, double(width_)), bx = std::clamp(hx, ax, double(width_));
  const double ay = std::clamp(ly, 0.0, double(height_)), by = std::clamp(hy, ay, double(height_));
  if (!(bx > ax && by > ay)) return {lo, hi};
  std::pair<int, int> sx, sy;
  const size_t l = coverLevel(ax, bx, ay, by, 1, sx, sy);
  for (int y = sy.first; y <= sy.second; ++y)
    for (int x = sx.first; x <= sx.second; ++x) {
      const auto& v = hsm_[l][size_t(y) * hsmSizes_[l].first + x];
      lo = std::min<double>(lo, v.first), hi = std::max<double>(hi, v.second);
    }
  return {lo, hi};
}

double VssmReference::fetch(int x, int y) const {
  if (x < 0 || y < 0 || x >= int(width_) || y >= int(height_)) return kInf;
  return depth_[size_t(y) * width_ + x];
}

// Bilinear-weighted depth comparisons around (u, v); NaN and empty texels are lit.
double VssmReference::bilinearLit(double u, double v, double depth) const {
  const double bx = std::floor(u - 0.5), by = std::floor(v - 0.5), fx = u - 0.5 - bx, fy = v - 0.5 - by;
  auto lit = [&](int dx, int dy) { return fetch(int(bx) + dx, int(by) + dy) < depth ? 0.0 : 1.0; };
  return (1 - fy) * ((1 - fx) * lit(0, 0) + fx * lit(1, 0)) + fy * ((1 - fx) * lit(0, 1) + fx * lit(1, 1));
}

double VssmReference::tapDepth(const Rx& r, double u, double v) const {
  return r.depth - r.bias - r.biasSlope * std::hypot(u - r.u, v - r.v);
}

// Similar triangles (Fernando 2005): penumbra half-width at the receiver, in texels.
double VssmReference::penumbraTexels(double receiver, double occluder) const {
  const double world = light_.spot ? light_.lightSize * (receiver - occluder) / std::max(occluder, 1e-20)
                                   : light_.lightSize * (receiver - occluder);
  return std::max(world, 0.0) / (light_.spot ? light_.texelScale * receiver : light_.texelScale);
}

// One sub-kernel: lit, normal (Chebyshev group) or, as a leaf, PCF. True when an inner node must be refined.
bool VssmReference::visit(const Rx& r, double lx, double ly, double hx, double hy, bool leaf, bool search,
                          Sums& s) const {
  ++s.visited;
  const auto [e1, e2] = boxMoments(lx, ly, hx, hy);
  const double area = (hx - lx) * (hy - ly);
  const double delta = r.tSlope * std::hypot(0.5 * (lx + hx) - r.u, 0.5 * (ly + hy) - r.v);
  const bool guarded =
      search && !leaf &&
      chebyshev(e1 + delta, std::max(e2 - e1 * e1, settings_.minVariance), r.t) > settings_.planarMaxLit;
  const double gapX = std::max({lx - r.u, r.u - hx, 0.0}), gapY = std::max({ly - r.v, r.v - hy, 0.0});
  if (e1 + r.tSlope * std::hypot(gapX, gapY) >= r.t && e2 - e1 * e1 < settings_.litVariance) {
    s.litArea += area;
  } else if (e1 + delta < r.t && !guarded) {
    s.m1 += (e1 + delta) * area, s.m2 += (e2 + 2 * delta * e1 + delta * delta) * area;
    s.vsmArea += area, s.shift += delta * area;
  } else if (!leaf) {
    return true;
  } else {
    const int k = settings_.leafTaps;
    double blocked = 0, depthSum = 0, lit = 0;
    for (int j = 0; j < k; ++j)
      for (int i = 0; i < k; ++i) {
        const double u = lx + (hx - lx) * (i + 0.5) / k, v = ly + (hy - ly) * (j + 0.5) / k;
        const double z = fetch(int(std::floor(u)), int(std::floor(v))), tap = tapDepth(r, u, v);
        if (search && z < tap) blocked += 1, depthSum += (z - light_.zNear) / (light_.zFar - light_.zNear);
        if (!search) lit += bilinearLit(u, v, tap);
      }
    s.pcfArea += area;
    s.pcfBlocked += search ? area * blocked / (k * k) : area * (1 - lit / (k * k));
    s.pcfDepth += area * depthSum / (k * k);
  }
  return false;
}

// Recursive quad-tree walk: children in the order (0,0), (1,0), (0,1), (1,1) of their 2x2 block; nodes at maxLevel
// are leaves.
void VssmReference::adaptive(const Rx& r, double lx, double ly, double sx, double sy, int level, int maxLevel,
                             bool search, Sums& s) const {
  const bool leaf = level == maxLevel;
  if (!visit(r, lx, ly, lx + sx, ly + sy, leaf, search, s) || leaf) return;
  for (int k = 0; k < 4; ++k)
    adaptive(r, lx + (k & 1) * sx / 2, ly + (k >> 1) * sy / 2, sx / 2, sy / 2, level + 1, maxLevel, search, s);
}

// The disk of half-width w as K equal-height strips, each the rectangle with the disk's area over its rows:
// half-width = (integral of sqrt(w^2 - y^2) over the rows) / (row height); K = min(diskStrips, ceil(2w / satReduce)).
std::vector<std::pair<std::array<double, 2>, std::array<double, 2>>> VssmReference::kernelBoxes(const Rx& r,
                                                                                                double w) const {
  if (settings_.diskStrips == 0) return {{{r.u - w, r.v - w}, {r.u + w, r.v + w}}};
  const int k = std::clamp(int(std::ceil(2 * w / settings_.satReduce)), 1, settings_.diskStrips);
  auto integral = [w](double y) {
    y = std::clamp(y, -w, w);
    return 0.5 * (y * std::sqrt(std::max(w * w - y * y, 0.0)) + w * w * std::asin(std::clamp(y / w, -1.0, 1.0)));
  };
  std::vector<std::pair<std::array<double, 2>, std::array<double, 2>>> boxes;
  const double h = 2 * w / k;
  for (int i = 0; i < k; ++i) {
    const double ya = -w + h * i, yb = ya + h;
    const double half = (integral(yb) - integral(ya)) / h;
    boxes.push_back({{r.u - half, r.v + ya}, {r.u + half, r.v + yb}});
  }
  return boxes;
}

std::pair<double, double> VssmReference::kernelMoments(const Rx& r, double w) const {
  double e1 = 0, e2 = 0, total = 0;
  for (const auto& [lo, hi] : kernelBoxes(r, w)) {
    const double area = (hi[0] - lo[0]) * (hi[1] - lo[1]);
    const auto [m1, m2] = boxMoments(lo[0], lo[1], hi[0], hi[1]);
    e1 += m1 * area, e2 += m2 * area, total += area;
  }
  return {e1 / total, e2 / total};
}

// Each strip subdivided as the square would be, its share of the budget: uniform d x ceil(d / K); adaptive a tree
// floor(log4 K) levels shallower (at least one level). No sub-kernel narrower than leafTaps texels: d at most
// ceil(2w / leafTaps), the tree at most floor(log2(2w / leafTaps)) levels (at least one).
void VssmReference::subdivide(const Rx& r, double w, bool search, Sums& s) const {
  const auto boxes = kernelBoxes(r, w);
  const int strips = int(boxes.size());
  const int scheme = search ? settings_.searchScheme : settings_.shadeScheme;
  const double side = 2.0 * w / settings_.leafTaps;
  int shallower = 0, resolved = 1;
  for (int q = 4; q <= strips; q *= 4) ++shallower;
  for (double q = 4.0; q <= side && resolved < 16; q *= 2.0) ++resolved;
  const int maxLevel = std::min(std::max(settings_.levels - shallower, 1), resolved);
  const int budget = search ? settings_.m : settings_.n;
  const int nx = static_cast<int>(std::clamp(std::ceil(side), 1.0, static_cast<double>(budget)));
  const int ny = (nx + strips - 1) / strips;
  for (const auto& [lo, hi] : boxes) {
    if (scheme == 2) {
      adaptive(r, lo[0], lo[1], hi[0] - lo[0], hi[1] - lo[1], 0, maxLevel, search, s);
      continue;
    }
    const double sx = (hi[0] - lo[0]) / nx, sy = (hi[1] - lo[1]) / ny;
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        visit(r, lo[0] + i * sx, lo[1] + j * sy, lo[0] + (i + 1) * sx, lo[1] + (j + 1) * sy, true, search, s);
  }
}

// vssm.cl vssm_node_may_block: node (x, y) of level l lies within min(w, its nearest depth's cone) and fails the
// strictest comparison a tap makes on it.
bool VssmReference::nodeMayBlock(const Rx& r, double w, size_t l, int x, int y) const {
  const auto [lw, lh] = hsmSizes_[l];
  const double nearest = hsm_[l][size_t(y) * lw + x].first;
  if (!(nearest < 1.0)) return false;  // nothing drawn nearer than the far plane
  const double nx = double(width_) / lw, ny = double(height_) / lh;
  const bool exact = (size_t(lw) << l) == width_ && (size_t(lh) << l) == height_;
  const double ox = exact ? 0.0 : nx, oy = exact ? 0.0 : ny;
  const double gx = std::max({x * nx - ox - r.u, r.u - (x + 1) * nx - ox, 0.0});
  const double gy = std::max({y * ny - oy - r.v, r.v - (y + 1) * ny - oy, 0.0});
  const double reach = std::hypot(gx, gy) - std::sqrt(2.0);
  const double invRange = 1.0 / (light_.zFar - light_.zNear);
  const double z = light_.zNear + nearest / invRange;
  const double cone = std::clamp(penumbraTexels(r.depth, std::max(z, light_.zNear)), 0.5, settings_.maxRadius);
  if (reach > std::min(w, cone)) return false;
  return nearest < r.t - r.tSlope * std::max(reach, 0.0);
}

// vssm.cl vssm_no_blocker: the nodes of the finest level covering the kernel's square (widened by a texel) with at
// most kNodes a side, each that may block replaced by its children on the next finer level (depth first, the same
// order, budget and stack as the kernel's), down to the map's texels.
bool VssmReference::noBlocker(const Rx& r, double w) const {
  constexpr int kNodes = 4, kBudget = 256;
  constexpr size_t kStack = 32;
  const double ax = std::clamp(r.u - w - 1, 0.0, double(width_)), bx = std::clamp(r.u + w + 1, ax, double(width_));
  const double ay = std::clamp(r.v - w - 1, 0.0, double(height_)), by = std::clamp(r.v + w + 1, ay, double(height_));
  if (!(bx > ax && by > ay)) return true;
  std::pair<int, int> sx, sy;
  const size_t top = coverLevel(ax, bx, ay, by, kNodes - 1, sx, sy);
  struct Node {
    size_t l;
    int x, y;
  };
  std::vector<Node> stack;
  int budget = kBudget;
  bool descended = false;
  for (int y0 = sy.first; y0 <= sy.second; ++y0)
    for (int x0 = sx.first; x0 <= sx.second; ++x0) {
      stack.assign(1, Node{top, x0, y0});
      while (!stack.empty()) {
        const Node n = stack.back();
        stack.pop_back();
        if (--budget < 0) return false;
        if (!nodeMayBlock(r, w, n.l, n.x, n.y)) continue;
        if (n.l == 0) return false;  // a texel that can block
        descended = true;
        const auto [fw, fh] = hsmSizes_[n.l - 1];
        const auto cx = span(ax, bx, width_, fw), cy = span(ay, by, height_, fh);
        const int nx = fw == 1 ? 1 : fw % 2 == 0 ? 2 : 3, ny = fh == 1 ? 1 : fh % 2 == 0 ? 2 : 3;
        const int fx = fw == 1 ? 0 : 2 * n.x, fy = fh == 1 ? 0 : 2 * n.y;
        for (int j = std::max(fy, cy.first); j <= std::min(fy + ny - 1, cy.second); ++j)
          for (int i = std::max(fx, cx.first); i <= std::min(fx + nx - 1, cx.second); ++i) {
            if (stack.size() == kStack) return false;
            stack.push_back(Node{n.l - 1, i, j});
          }
      }
    }
  descents_ += descended;
  return true;
}

double VssmReference::blocker(const Rx& r, double w, double zmin, bool& subdivided, int& visited) const {
  if (settings_.searchScheme != 0 && settings_.searchNarrowings > 0 && noBlocker(r, w)) return -1;
  const auto [e1, e2] = kernelMoments(r, w);
  const double minVar = settings_.minVariance;
  if (e1 < r.t) {
    const double var = std::max(e2 - e1 * e1, minVar);
    if (chebyshev(e1, var, r.t) <= settings_.planarMaxLit || settings_.searchScheme == 0) {
      const double zocc = occluderDepth(e1, var, r.t);
      if (stacked(zocc, zmin, r.t)) return stackedTaps(r, w, true);
      return std::clamp(zocc, zmin, r.t);
    }
  }
  if (settings_.searchScheme == 0) return -1;
  subdivided = true;
  Sums s;
  subdivide(r, w, true, s);
  visited += s.visited;
  double blocked = s.pcfBlocked, depthSum = s.pcfDepth;
  if (s.vsmArea > 0) {
    const double mean = s.m1 / s.vsmArea, var = std::max(s.m2 / s.vsmArea - mean * mean, minVar);
    const double area = (1 - chebyshev(mean, var, r.t)) * s.vsmArea;
    if (area > 0 && stacked(occluderDepth(mean, var, r.t), zmin, r.t)) return stackedTaps(r, w, true);
    if (area > 0) {
      blocked += area;
      depthSum += std::clamp(occluderDepth(mean, var, r.t) - s.shift / s.vsmArea, zmin, r.t) * area;
    }
  }
  return blocked > 0 ? depthSum / blocked : -1;
}

// vssm.cl vssm_lit_share: Chebyshev's bound, with firstMoment capped by (E(x) - zocc) / (t - zocc).
double VssmReference::litShare(const Rx& r, double mean, double variance, double zocc) const {
  const double bound = chebyshev(mean, variance, r.t);
  if (!settings_.firstMoment || !(zocc < r.t)) return bound;
  return std::min(bound, std::clamp((mean - zocc) / (r.t - zocc), 0.0, 1.0));
}

double VssmReference::shade(const Rx& r, double w, double zocc, bool& subdivided, int& visited, int& path) const {
  const auto [zmin, zmax] = hsmRange(r.u - w, r.v - w, r.u + w, r.v + w);  // the penumbra kernel's square
  if (zmin >= r.t) {
    path = 0;
    return 1;
  }
  if (zmax < r.t - r.tSlope * w * std::sqrt(2.0)) {
    path = 1;
    return 0;
  }
  const auto [e1, e2] = kernelMoments(r, w);
  const double minVar = settings_.minVariance;
  if (e1 < r.t) {
    // A receiver whose own plane moves across the kernel by more than tiltShare of the gap between the blocker depth
    // and t is no receiver at one depth t, which L20's bound reads (vssm.cl): the jittered taps instead.
    if (settings_.tiltShare > 0 && r.tSlope * w > settings_.tiltShare * (r.t - zocc)) {
      path = 7;
      return stackedTaps(r, w, false);
    }
    const double var = std::max(e2 - e1 * e1, minVar);
    if (stacked(occluderDepth(e1, var, r.t), zmin, r.t)) {
      path = 6;
      return stackedTaps(r, w, false);
    }
    return litShare(r, e1, var, zocc);
  }
  if (settings_.shadeScheme == 0) return 1;
  subdivided = true;
  Sums s;
  subdivide(r, w, false, s);
  visited += s.visited;
  double lit = s.litArea + s.pcfArea - s.pcfBlocked;
  if (s.vsmArea > 0) {
    const double mean = s.m1 / s.vsmArea;
    lit += litShare(r, mean, std::max(s.m2 / s.vsmArea - mean * mean, minVar), zocc) * s.vsmArea;
  }
  return std::clamp(lit / (s.litArea + s.vsmArea + s.pcfArea), 0.0, 1.0);
}

double VssmReference::contact(const Rx& r, double lo[2], double hi[2]) const {
  double lit = 0;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      const uint32_t tap = r.seed * 18u + uint32_t(j * 3 + i) * 2u;
      const double u = lo[0] + (hi[0] - lo[0]) / 3 * (i + hash01(tap));
      const double v = lo[1] + (hi[1] - lo[1]) / 3 * (j + hash01(tap + 1u));
      lit += bilinearLit(u, v, tapDepth(r, u, v));
    }
  return lit / 9;
}

bool VssmReference::stacked(double zocc, double zmin, double t) const {
  return settings_.stackedSpread > 0 && zocc - zmin > settings_.stackedSpread * (t - zmin);
}

// stackedTaps^2 jittered cells over the kernel's square; on a disk kernel the taps inside it (vssm.cl).
double VssmReference::stackedTaps(const Rx& r, double w, bool search) const {
  const int taps = settings_.stackedTaps;
  const uint32_t n = uint32_t(taps * taps);
  const double cell = 2 * w / taps, invRange = 1.0 / (light_.zFar - light_.zNear);
  double sum = 0, blocked = 0;
  int count = 0;
  for (int j = 0; j < taps; ++j)
    for (int i = 0; i < taps; ++i) {
      const uint32_t tap = (r.seed * 2u * n + (search ? n : 0u) + uint32_t(j * taps + i)) * 2u;
      const double u = r.u - w + cell * (i + hash01(tap)), v = r.v - w + cell * (j + hash01(tap + 1u));
      if (settings_.diskStrips != 0 && std::hypot(u - r.u, v - r.v) > w) continue;
      ++count;
      if (!search) {
        sum += bilinearLit(u, v, tapDepth(r, u, v));
        continue;
      }
      const double z = fetch(int(std::floor(u)), int(std::floor(v)));
      if (z < tapDepth(r, u, v)) blocked += 1, sum += (z - light_.zNear) * invRange;
    }
  if (search) return blocked > 0 ? sum / blocked : -1;
  return count > 0 ? sum / count : bilinearLit(r.u, r.v, tapDepth(r, r.u, r.v));
}

VssmResult VssmReference::pixel(const VssmReceiverIn& in) const {
  const double invRange = 1.0 / (light_.zFar - light_.zNear);
  const double t = std::min((in.depth - in.bias - light_.zNear) * invRange, 1.0);  // nothing lies beyond far
  const Rx r{in.u, in.v, in.depth, in.bias, in.biasSlope, t, in.biasSlope * invRange, in.seed};
  VssmResult out;
  double wi = std::clamp(penumbraTexels(in.depth, light_.zNear), 0.5, settings_.maxRadius);
  double zmin = 0, zmax = 0;
  for (int step = 0;; ++step) {
    std::tie(zmin, zmax) = hsmRange(in.u - wi, in.v - wi, in.u + wi, in.v + wi);
    if (zmin >= r.t) return out;                                              // every tap lit
    if (zmax < r.t - r.tSlope * wi * std::sqrt(2.0)) return {0, 0, 0, 0, 1};  // every tap blocked
    if (step >= settings_.searchNarrowings) break;
    // The light's cone cut at the nearest texel's depth (vssm.cl).
    const double nearest = light_.zNear + zmin / invRange;
    const double narrowed =
        std::clamp(penumbraTexels(in.depth, std::max(nearest, light_.zNear)), 0.5, settings_.maxRadius);
    if (!(narrowed < wi)) break;
    wi = narrowed;
  }
  bool subdivided = false;
  const double zocc = blocker(r, wi, zmin, subdivided, out.visited);
  if (zocc < 0) return {1, 0, 0, out.visited, 5};
  out.blocker = light_.zNear + zocc / invRange;
  out.penumbra = std::clamp(penumbraTexels(in.depth, out.blocker), 0.5, settings_.maxRadius);
  const double wp = out.penumbra;
  double plo[2] = {in.u - wp, in.v - wp}, phi[2] = {in.u + wp, in.v + wp};
  if (in.depth - out.blocker < settings_.contactDepth) {
    out.visibility = contact(r, plo, phi);
    out.path = 4;
    return out;
  }
  int path = -1;
  out.visibility = shade(r, wp, zocc, subdivided, out.visited, path);
  out.path = path >= 0 ? path : subdivided ? 3 : 2;
  return out;
}

}  // namespace penumbra::ref
