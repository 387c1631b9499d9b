// Block means of the reference moments (computeMomentsReduced's reference). Apart from moments_ref.cpp, which the API
// tests compile without the library (this one needs its momentChannels and reducedExtent).
#include <limits>

#include "tools/selftest/reference/moments_ref.h"

namespace penumbra::ref {

std::vector<double> momentBlockMeans(const std::vector<float>& depth, uint32_t width, uint32_t height,
                                     const MomentsConfig& config, uint32_t factor) {
  const std::vector<double> texel = moments(depth, config);
  const std::vector<double> empty = moments({std::numeric_limits<float>::infinity()}, config);
  const size_t channels = momentChannels(config.kind);
  const uint32_t outWidth = reducedExtent(width, factor), outHeight = reducedExtent(height, factor);
  std::vector<double> out(size_t(outWidth) * outHeight * channels, 0.0);
  for (uint32_t y = 0; y < outHeight; ++y)
    for (uint32_t x = 0; x < outWidth; ++x)
      for (uint32_t j = y * factor; j < (y + 1) * factor; ++j)
        for (uint32_t i = x * factor; i < (x + 1) * factor; ++i)
          for (size_t c = 0; c < channels; ++c) {
            const double v = i < width && j < height ? texel[(size_t(j) * width + i) * channels + c] : empty[c];
            out[(size_t(y) * outWidth + x) * channels + c] += v / double(factor * factor);
          }
  return out;
}

}  // namespace penumbra::ref
