// Double-precision and exact-integer references of the SAT stage: inclusive 2-D prefix sums, the
// fixed-point quantization the kernels use, and the exact integral of the image over a continuous box.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "host/stages/image_shape.h"

namespace penumbra::ref {

// SAT of (x - offset[channel]) in double; NaN and infinities propagate as IEEE arithmetic says.
std::vector<double> satDouble(const std::vector<float>& image, const ImageShape& shape,
                              const std::array<double, 4>& offset = {});

// round-half-even(x * 2^bits) saturated to the signed range of U (NaN -> 0), summed modulo 2^(8 sizeof U).
template <class U>
std::vector<U> satFixed(const std::vector<float>& image, const ImageShape& shape, int fractionBits);

// Per-channel mean of the finite texels (0 where none).
std::array<double, 4> finiteMean(const std::vector<float>& image, const ImageShape& shape);

// Sum over the finite texels of |x - offset[channel]|: the magnitude a floating-point table's rounding scales with
// (satTableTolerance, tolerance.h).
double satMagnitude(const std::vector<float>& image, const std::array<double, 4>& offset, uint32_t channels);

// The integral over [lo.x, hi.x] x [lo.y, hi.y] (texel (x, y) covers [x, x+1] x [y, y+1]) of the
// piecewise-constant image, the box clamped to the image; one value per channel.
std::array<double, 4> boxIntegral(const std::vector<float>& image, const ImageShape& shape, double loX, double loY,
                                  double hiX, double hiY);

}  // namespace penumbra::ref
