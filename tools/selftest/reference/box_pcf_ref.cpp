// Box PCF reference: a clamp-to-edge box filter of the occlusion flags (blur_ref's separable convolution),
// then a bilinear read.
#include "tools/selftest/reference/box_pcf_ref.h"

#include <algorithm>
#include <cmath>

#include "tools/selftest/reference/blur_ref.h"

namespace penumbra::ref {

BoxPcf::BoxPcf(const std::vector<double>& occluded, int size, int radius) : size_(size) {
  const ImageShape shape{static_cast<uint32_t>(size), static_cast<uint32_t>(size), 1};
  filtered_ = convolveSeparable(occluded, shape, boxTaps(radius));
}

double BoxPcf::visibility(glm::dvec2 texel) const {
  const glm::dvec2 t = texel - 0.5, base = glm::floor(t), w = t - base;
  auto at = [&](int x, int y) {
    x = std::clamp(x, 0, size_ - 1), y = std::clamp(y, 0, size_ - 1);
    return filtered_[size_t(y) * size_ + x];
  };
  const int x = static_cast<int>(base.x), y = static_cast<int>(base.y);
  const double bottom = at(x, y) * (1 - w.x) + at(x + 1, y) * w.x;
  const double top = at(x, y + 1) * (1 - w.x) + at(x + 1, y + 1) * w.x;
  return 1.0 - (bottom * (1 - w.y) + top * w.y);
}

}  // namespace penumbra::ref
