// The shape of an image the filtering stages read or write: width x height texels of `channels`
// interleaved floats (1, 2 or 4; three channels use the 4-channel layout), rows bottom to top, no padding.
#pragma once

#include <fmt/format.h>

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace penumbra {

struct ImageShape {
  uint32_t width = 0, height = 0;
  uint32_t channels = 1;

  size_t texels() const { return size_t(width) * height; }
  size_t count() const { return texels() * channels; }  // scalars
};

// Throws std::invalid_argument naming the stage unless the shape is usable (channels 1, 2 or 4, sizes
// below 2^15 so that texel indices and 32-bit fixed-point tile sums stay in range).
inline void checkShape(const ImageShape& shape, const std::string& stage) {
  if (shape.channels != 1 && shape.channels != 2 && shape.channels != 4)
    throw std::invalid_argument(fmt::format("{}: {} channels (1, 2 or 4; use 4 for 3)", stage, shape.channels));
  if (shape.width > 32768 || shape.height > 32768)
    throw std::invalid_argument(fmt::format("{}: image {}x{} larger than 32768", stage, shape.width, shape.height));
}

// Throws std::invalid_argument unless a buffer of `size` elements holds at least `needed`.
inline void checkBufferSize(size_t size, size_t needed, const std::string& stage, const char* what) {
  if (size < needed)
    throw std::invalid_argument(fmt::format("{}: {} buffer holds {} elements, needs {}", stage, what, size, needed));
}

}  // namespace penumbra
