// Double-precision reference of the separable blur: a naive clamp-to-edge convolution with explicit taps.
#pragma once

#include <cstdint>
#include <vector>

#include "host/stages/blur.h"
#include "host/stages/image_shape.h"

namespace penumbra::ref {

// Normalised Gaussian taps exp(-k^2 / (2 sigma^2)) for k in [-ceil(3 sigma), ceil(3 sigma)].
std::vector<double> gaussianTaps(double sigma);
std::vector<double> boxTaps(int radius);  // 2 radius + 1 taps of 1 / (2 radius + 1)

// Convolves every channel along rows, then along columns, with `taps` (odd count, centred),
// clamping coordinates to the image.
std::vector<double> convolveSeparable(const std::vector<double>& image, const ImageShape& shape,
                                      const std::vector<double>& taps);

// ESM's log-space blur (kernels/shared/moments.h moments_log_mix), in double around each output's largest tap: the D
// with e^(c D) = sum over rows of w_j (sum over columns of w_i e^(c d_ij)), clamp-to-edge; the linear blur for c = 0.
std::vector<double> logBlur(const std::vector<double>& d, uint32_t width, uint32_t height,
                            const std::vector<double>& taps, double c);

// What the blur stage computes for `config`: its plan's taps (direct plans) or its boxes one after another (running
// sums), from planBlur.
std::vector<double> blurExpected(const std::vector<double>& image, const ImageShape& shape, const BlurConfig& config);

}  // namespace penumbra::ref
