// 8-bit PNG previews (libpng, written row by row) and the display encodings they use: linear RGB(A) through
// exposure and the sRGB transfer function (IEC 61966-2-1, piecewise, not a 2.2 gamma), and scalar
// images (error maps) through viridis (van der Walt & Smith, matplotlib 2015). NaN -> magenta.
// Writes are all-or-nothing; failures throw std::runtime_error naming the path.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

#include "host/io/atomic_file.h"
#include "host/io/image.h"
#include "host/io/image_rows.h"

namespace penumbra {

using Rgb8 = std::array<std::uint8_t, 3>;

// Loud magenta: appears in neither viridis nor typical renders, so a NaN pixel is never mistaken
// for data.
inline constexpr Rgb8 kNanColour = {255, 0, 255};

// Linear-light value to the sRGB-encoded value, both in [0, 1]: 12.92 x up to 0.0031308, then
// 1.055 x^(1/2.4) - 0.055. Input is clamped to [0, 1] first; NaN is passed through.
float srgbEncode(float linear);

// Linear-light value to an 8-bit sRGB code (round to nearest): 0 -> 0, 1 -> 255, 0.5 -> 188.
// NaN -> 0 (callers that want kNanColour test for NaN first, per pixel).
std::uint8_t srgbByte(float linear);

// A value in [0, 1] stored as-is (no transfer function), e.g. alpha. NaN -> 0.
std::uint8_t unormByte(float value);

// Viridis at t in [0, 1] (clamped), as 8-bit sRGB. t = 0 -> (68, 1, 84), t = 1 -> (253, 231, 37).
// NaN -> kNanColour.
Rgb8 viridis(float t);

// `value` mapped linearly from [lo, hi] onto viridis; NaN -> kNanColour, values outside (and +-Inf)
// clamp to the ends. A degenerate range (lo >= hi) gives the top colour above hi, the bottom one
// otherwise, so a constant error image still renders.
Rgb8 falseColour(float value, float lo, float hi);

struct PngOptions {
  // Stops: linear values are multiplied by 2^exposure before encoding.
  float exposure = 0.0f;
  // When set, this channel (e.g. "visibility.Y") is shown as grey instead of R, G, B (and A).
  std::string greyChannel;
  // The rows of R, G, B, A read at a time, in about this many bytes of floats (tests make it small).
  size_t bandBytes = size_t{8} << 20;
  // When set, the written and synced file is renamed into place by the group's commit() (ExrOptions::commitGroup).
  CommitGroup* commitGroup = nullptr;
};

// Writes channels R, G, B (required, else the error names the missing channel), plus A when the
// image has one. RGB is taken as premultiplied by A, as in EXR, and un-premultiplied for PNG's
// straight alpha. A pixel with a NaN in any used channel is opaque magenta; +-Inf clamp.
// The rows are read in bands of a few MiB, so a frame whose channels stay on the device (ImageRows' deferred
// channels) is never whole on the host.
void writePngPreview(const std::filesystem::path& path, const Image& image, const PngOptions& options = {});
void writePngPreview(const std::filesystem::path& path, const ImageRows& image, const PngOptions& options = {});

// Writes a width x height scalar image (row 0 at the top) mapped from [lo, hi] onto viridis
// (see falseColour()); NaN -> magenta. Throws std::invalid_argument when values.size()
// != width*height, the size is not positive, or lo/hi are NaN or lo > hi.
void writePngFalseColour(const std::filesystem::path& path, int width, int height, std::span<const float> values,
                         float lo, float hi);

}  // namespace penumbra
