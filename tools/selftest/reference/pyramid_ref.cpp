// Naive pyramids: footprints integrated texel by texel over the previous level.
#include "tools/selftest/reference/pyramid_ref.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace penumbra::ref {
namespace {

// Overlap of destination texel `x` (of `dst`) with source texel `i` (of `src`), in source texels.
double overlap(uint32_t x, uint32_t dst, uint32_t i, uint32_t src) {
  const double lo = double(x) * src / dst, hi = double(x + 1) * src / dst;
  return std::max(0.0, std::min(hi, i + 1.0) - std::max(lo, double(i)));
}

}  // namespace

std::vector<std::vector<double>> momentMips(const std::vector<double>& base, const ImageShape& shape) {
  std::vector<std::vector<double>> levels;
  std::vector<double> src = base;
  uint32_t sw = shape.width, sh = shape.height;
  const uint32_t c = shape.channels;
  while (sw > 1 || sh > 1) {
    const uint32_t dw = std::max(1u, sw / 2), dh = std::max(1u, sh / 2);
    std::vector<double> dst(size_t(dw) * dh * c, 0.0);
    for (uint32_t y = 0; y < dh; ++y)
      for (uint32_t x = 0; x < dw; ++x) {
        double area = 0.0;
        for (uint32_t j = 0; j < sh; ++j)
          for (uint32_t i = 0; i < sw; ++i) {
            const double a = overlap(x, dw, i, sw) * overlap(y, dh, j, sh);
            if (a == 0.0) continue;
            area += a;
            for (uint32_t ch = 0; ch < c; ++ch)
              dst[(size_t(y) * dw + x) * c + ch] += a * src[(size_t(j) * sw + i) * c + ch];
          }
        for (uint32_t ch = 0; ch < c; ++ch) dst[(size_t(y) * dw + x) * c + ch] /= area;
      }
    levels.push_back(dst);
    src = std::move(dst);
    sw = dw, sh = dh;
  }
  return levels;
}

std::vector<std::vector<std::pair<float, float>>> minMaxPyramid(const std::vector<float>& depth, uint32_t width,
                                                                uint32_t height) {
  constexpr float kInf = std::numeric_limits<float>::infinity();
  std::vector<std::vector<std::pair<float, float>>> levels(1);
  for (float d : depth) levels[0].push_back(std::isfinite(d) ? std::pair{d, d} : std::pair{kInf, -kInf});
  uint32_t sw = width, sh = height;
  while (sw > 1 || sh > 1) {
    const uint32_t dw = std::max(1u, sw / 2), dh = std::max(1u, sh / 2);
    std::vector<std::pair<float, float>> dst(size_t(dw) * dh, {kInf, -kInf});
    const auto& src = levels.back();
    for (uint32_t y = 0; y < dh; ++y)
      for (uint32_t x = 0; x < dw; ++x)
        for (uint32_t j = 0; j < sh; ++j)
          for (uint32_t i = 0; i < sw; ++i)
            if (overlap(x, dw, i, sw) > 0.0 && overlap(y, dh, j, sh) > 0.0) {
              auto& r = dst[size_t(y) * dw + x];
              r.first = std::min(r.first, src[size_t(j) * sw + i].first);
              r.second = std::max(r.second, src[size_t(j) * sw + i].second);
            }
    levels.push_back(std::move(dst));
    sw = dw, sh = dh;
  }
  return levels;
}

}  // namespace penumbra::ref
