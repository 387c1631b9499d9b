// The blur stage's expected output for a configuration: its plan (host/stages/blur.cpp's planBlur, library code)
// applied with the naive convolution. Apart from blur_ref.cpp, which the API tests compile without the library.
#include "tools/selftest/reference/blur_ref.h"

namespace penumbra::ref {

std::vector<double> blurExpected(const std::vector<double>& image, const ImageShape& shape, const BlurConfig& config) {
  const BlurPlan plan = planBlur(config);
  if (plan.direct)
    return convolveSeparable(
        image, shape,
        config.filter == BlurFilter::Gaussian ? gaussianTaps(config.sigma * config.scale) : boxTaps(plan.radius));
  std::vector<double> out = image;
  for (int r : plan.boxRadii) out = convolveSeparable(out, shape, boxTaps(r));
  return out;
}

}  // namespace penumbra::ref
