// Double-precision reference of the separable blur: a naive clamp-to-edge convolution with explicit taps.
#pragma once

#include <vector>

#include "host/stages/image_shape.h"

namespace penumbra::ref {

// Normalised Gaussian taps exp(-k^2 / (2 sigma^2)) for k in [-ceil(3 sigma), ceil(3 sigma)].
std::vector<double> gaussianTaps(double sigma);
std::vector<double> boxTaps(int radius);  // 2 radius + 1 taps of 1 / (2 radius + 1)

// Convolves every channel along rows, then along columns, with `taps` (odd count, centred),
// clamping coordinates to the image.
std::vector<double> convolveSeparable(const std::vector<double>& image, const ImageShape& shape,
                                      const std::vector<double>& taps);

}  // namespace penumbra::ref
