// Naive clamp-to-edge separable convolution in double precision.
#include "tools/selftest/reference/blur_ref.h"

#include <algorithm>
#include <cmath>

namespace penumbra::ref {

std::vector<double> gaussianTaps(double sigma) {
  const int r = static_cast<int>(std::ceil(3.0 * sigma));
  std::vector<double> taps;
  for (int k = -r; k <= r; ++k) taps.push_back(r == 0 ? 1.0 : std::exp(-double(k * k) / (2.0 * sigma * sigma)));
  double total = 0.0;
  for (double t : taps) total += t;
  for (double& t : taps) t /= total;
  return taps;
}

std::vector<double> boxTaps(int radius) { return std::vector<double>(2 * radius + 1, 1.0 / (2 * radius + 1)); }

std::vector<double> convolveSeparable(const std::vector<double>& image, const ImageShape& shape,
                                      const std::vector<double>& taps) {
  const int w = int(shape.width), h = int(shape.height), c = int(shape.channels), r = int(taps.size() / 2);
  auto at = [&](const std::vector<double>& img, int x, int y, int ch) {
    return img[(size_t(std::clamp(y, 0, h - 1)) * w + std::clamp(x, 0, w - 1)) * c + ch];
  };
  std::vector<double> rows(image.size()), out(image.size());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int ch = 0; ch < c; ++ch) {
        double sum = 0.0;
        for (int k = -r; k <= r; ++k) sum += taps[k + r] * at(image, x + k, y, ch);
        rows[(size_t(y) * w + x) * c + ch] = sum;
      }
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int ch = 0; ch < c; ++ch) {
        double sum = 0.0;
        for (int k = -r; k <= r; ++k) sum += taps[k + r] * at(rows, x, y + k, ch);
        out[(size_t(y) * w + x) * c + ch] = sum;
      }
  return out;
}

std::vector<double> logBlur(const std::vector<double>& d, uint32_t width, uint32_t height,
                            const std::vector<double>& taps, double c) {
  const int r = static_cast<int>(taps.size() / 2);
  const auto pass = [&](const std::vector<double>& in, bool rows) {
    std::vector<double> out(in.size());
    for (int y = 0; y < int(height); ++y)
      for (int x = 0; x < int(width); ++x) {
        const auto at = [&](int k) {
          return rows ? in[size_t(y) * width + std::clamp(x - r + k, 0, int(width) - 1)]
                      : in[size_t(std::clamp(y - r + k, 0, int(height) - 1)) * width + x];
        };
        double m = -INFINITY, sum = 0.0, linear = 0.0;
        for (int k = 0; k <= 2 * r; ++k) m = std::max(m, at(k));
        for (int k = 0; k <= 2 * r; ++k) sum += taps[k] * std::exp(c * (at(k) - m)), linear += taps[k] * at(k);
        out[size_t(y) * width + x] = c == 0.0 ? linear : m + std::log(sum) / c;
      }
    return out;
  };
  return pass(pass(d, true), false);
}

}  // namespace penumbra::ref
