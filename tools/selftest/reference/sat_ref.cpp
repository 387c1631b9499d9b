// Naive summed-area tables: the running row sum plus the entry above, texel by texel.
#include "tools/selftest/reference/sat_ref.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace penumbra::ref {

std::vector<double> satDouble(const std::vector<float>& image, const ImageShape& shape,
                              const std::array<double, 4>& offset) {
  const size_t w = shape.width, h = shape.height, c = shape.channels;
  std::vector<double> out(image.size());
  for (size_t ch = 0; ch < c; ++ch)
    for (size_t y = 0; y < h; ++y) {
      double row = 0.0;
      for (size_t x = 0; x < w; ++x) {
        const size_t i = (y * w + x) * c + ch;
        row += double(image[i]) - offset[ch];
        out[i] = row + (y > 0 ? out[i - w * c] : 0.0);
      }
    }
  return out;
}

template <class U>
std::vector<U> satFixed(const std::vector<float>& image, const ImageShape& shape, int fractionBits) {
  using S = std::make_signed_t<U>;
  const double lo = double(std::numeric_limits<S>::min()), hi = -lo;  // hi = 2^(bits-1), not representable
  const size_t w = shape.width, h = shape.height, c = shape.channels;
  std::vector<U> out(image.size());
  for (size_t ch = 0; ch < c; ++ch)
    for (size_t y = 0; y < h; ++y) {
      U row = 0;
      for (size_t x = 0; x < w; ++x) {
        const size_t i = (y * w + x) * c + ch;
        const double v = std::nearbyint(std::ldexp(double(image[i]), fractionBits));
        const S q = std::isnan(v) ? 0
                    : v >= hi     ? std::numeric_limits<S>::max()
                    : v <= lo     ? std::numeric_limits<S>::min()
                                  : S(v);
        row += U(q);
        out[i] = U(row + (y > 0 ? out[i - w * c] : U(0)));
      }
    }
  return out;
}

template std::vector<uint32_t> satFixed(const std::vector<float>&, const ImageShape&, int);
template std::vector<uint64_t> satFixed(const std::vector<float>&, const ImageShape&, int);

std::array<double, 4> finiteMean(const std::vector<float>& image, const ImageShape& shape) {
  std::array<double, 4> sum{}, count{};
  for (size_t i = 0; i < image.size(); ++i)
    if (std::isfinite(image[i])) sum[i % shape.channels] += image[i], count[i % shape.channels] += 1.0;
  for (int ch = 0; ch < 4; ++ch) sum[ch] = count[ch] > 0 ? sum[ch] / count[ch] : 0.0;
  return sum;
}

std::array<double, 4> boxIntegral(const std::vector<float>& image, const ImageShape& shape, double loX, double loY,
                                  double hiX, double hiY) {
  loX = std::clamp(loX, 0.0, double(shape.width)), hiX = std::clamp(hiX, loX, double(shape.width));
  loY = std::clamp(loY, 0.0, double(shape.height)), hiY = std::clamp(hiY, loY, double(shape.height));
  std::array<double, 4> out{};
  for (size_t y = 0; y < shape.height; ++y) {
    const double cy = std::max(0.0, std::min(hiY, y + 1.0) - std::max(loY, double(y)));
    if (cy == 0.0) continue;
    for (size_t x = 0; x < shape.width; ++x) {
      const double cx = std::max(0.0, std::min(hiX, x + 1.0) - std::max(loX, double(x)));
      if (cx == 0.0) continue;
      for (size_t ch = 0; ch < shape.channels; ++ch)
        out[ch] += cx * cy * image[(y * shape.width + x) * shape.channels + ch];
    }
  }
  return out;
}

double satMagnitude(const std::vector<float>& image, const std::array<double, 4>& offset, uint32_t channels) {
  double sum = 0.0;
  for (size_t i = 0; i < image.size(); ++i)
    if (std::isfinite(image[i])) sum += std::abs(image[i] - offset[i % channels]);
  return sum;
}

}  // namespace penumbra::ref
