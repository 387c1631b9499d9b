// izb's light pattern and its bitmask tables (host/techniques/izb_pattern.h).
#include "host/techniques/izb_pattern.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "host/scene/light.h"
#include "kernels/shared/izb.h"

namespace penumbra {
namespace {

// The polar angle in [0, 2 pi] of diamond angle p in [0, 4] (kernels/shared/izb.h izb_mask_angle_bin): quadrant
// floor(p) holds the direction (1 - q, q) turned by that many quarter turns, q = p - floor(p).
double diamondToAngle(double p) {
  if (p >= 4.0) return 2.0 * std::numbers::pi;
  const double quadrant = std::floor(p), q = p - quadrant;
  return std::atan2(q, 1.0 - q) + quadrant * std::numbers::pi / 2.0;
}

// tan of the angle whose 1 - cos is x (0 <= x < 1).
double tanOfOneMinusCos(double x) { return std::sqrt(std::max(0.0, x * (2.0 - x))) / (1.0 - x); }

}  // namespace

IzbLightPattern::IzbLightPattern(int grid) : grid_(grid) {
  if (izb_light_grid_of(grid * grid) != grid)
    throw std::invalid_argument(
        fmt::format("izb light pattern: grid {} is outside {}..{}", grid, IZB_MIN_LIGHT_GRID, IZB_MAX_LIGHT_GRID));
  const auto k = static_cast<uint>(grid);
  for (uint j = 0; j < k * k; ++j)
    points_.push_back(concentricDisk({(static_cast<float>(j % k) + izb_jitter(j, 0u)) / static_cast<float>(k),
                                      (static_cast<float>(j / k) + izb_jitter(j, 1u)) / static_cast<float>(k)}));
  for (int r = 0; r < IZB_ROTATIONS; ++r) {
    const double angle = 2.0 * std::numbers::pi * r / IZB_ROTATIONS;
    rotations_.emplace_back(static_cast<float>(std::cos(angle)), static_cast<float>(std::sin(angle)));
  }
}

glm::vec2 IzbLightPattern::point(uint32_t key, int j) const {
  const glm::vec2 cs = rotations_[izb_rotation_of(key)], p = points_[static_cast<size_t>(j)];
  // As izb_soft_test: products first, then the sums (no fused multiply-add there).
  const float cx = cs.x * p.x, sy = cs.y * p.y, sx = cs.y * p.x, cy = cs.x * p.y;
  return {cx - sy, sx + cy};
}

std::vector<glm::dvec2> IzbLightPattern::planePoints(bool sun, float oneMinusCos) const {
  std::vector<glm::dvec2> plane;
  const double tanAlpha = sun ? tanOfOneMinusCos(oneMinusCos) : 1.0;
  for (const glm::vec2& p : points_) {
    const glm::dvec2 q(p);
    const double r = glm::length(q);
    plane.push_back(!sun || r == 0.0 ? q : q * (tanOfOneMinusCos(r * r * oneMinusCos) / (tanAlpha * r)));
  }
  return plane;
}

std::vector<uint32_t> IzbLightPattern::masks(bool sun, float oneMinusCos, float margin) const {
  const int n = count(), words = izb_mask_words(n);
  const std::vector<glm::dvec2> plane = planePoints(sun, oneMinusCos);
  std::vector<uint32_t> out(static_cast<size_t>(IZB_MASK_ANGLES) * IZB_MASK_OFFSETS * 2 * words, 0u);
  constexpr double kPi = std::numbers::pi;
  for (int a = 0; a < IZB_MASK_ANGLES; ++a) {
    // The bin's normals: diamond angles [4 a / A, 4 (a + 1) / A), polar angles [a0, a1), widened by 1e-6 against the
    // rounding of the kernel's diamond angle.
    const double a0 = diamondToAngle(4.0 * a / IZB_MASK_ANGLES) - 1e-6;
    const double a1 = diamondToAngle(4.0 * (a + 1) / IZB_MASK_ANGLES) + 1e-6;
    // Per point, the least and greatest n(angle) . p over the bin: at its ends, or at the point's own direction
    // (greatest) or its opposite (least) where they fall inside it.
    std::vector<double> lo(static_cast<size_t>(n)), hi(static_cast<size_t>(n));
    for (int j = 0; j < n; ++j) {
      const glm::dvec2 q = plane[static_cast<size_t>(j)];
      const double s0 = q.x * std::cos(a0) + q.y * std::sin(a0), s1 = q.x * std::cos(a1) + q.y * std::sin(a1);
      double l = std::min(s0, s1), h = std::max(s0, s1);
      const double r = glm::length(q), own = std::atan2(q.y, q.x);
      for (double turn : {0.0, kPi}) {
        double angle = own + turn;
        while (angle >= a1) angle -= 2.0 * kPi;
        while (angle < a0) angle += 2.0 * kPi;
        if (angle < a1) (turn == 0.0 ? h : l) = turn == 0.0 ? r : -r;
      }
      lo[static_cast<size_t>(j)] = l, hi[static_cast<size_t>(j)] = h;
    }
    for (int b = 0; b < IZB_MASK_OFFSETS; ++b) {
      const double d0 = -1.0 + 2.0 * b / IZB_MASK_OFFSETS, d1 = -1.0 + 2.0 * (b + 1) / IZB_MASK_OFFSETS;
      uint32_t* may = &out[((static_cast<size_t>(a) * IZB_MASK_OFFSETS + b) * 2) * words];
      uint32_t* certain = may + words;
      for (int j = 0; j < n; ++j) {
        const uint32_t bit = 1u << (j % 32);
        // An edge of this bin (angle in [a0, a1), offset in [d0, d1)) has p inside when n . p >= offset.
        if (hi[static_cast<size_t>(j)] >= d0 - margin) may[j / 32] |= bit;
        if (lo[static_cast<size_t>(j)] > d1 + margin) certain[j / 32] |= bit;
      }
    }
  }
  return out;
}

}  // namespace penumbra
