// ImageRows: name lookups over an Image's channels and the deferred ones, and band reads with their range checks.
#include "host/io/image_rows.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <stdexcept>

namespace penumbra {
namespace {

std::string displayName(const Image& image) { return image.source().empty() ? "image" : image.source(); }

}  // namespace

ImageRows::ImageRows(const Image& image, std::span<const DeferredChannel> deferred)
    : image_(image), deferred_(deferred), names_(image.channelNames()) {
  for (const DeferredChannel& channel : deferred_) {
    if (channel.name.empty())
      throw std::invalid_argument(fmt::format("{}: deferred channel name is empty", displayName(image_)));
    if (has(channel.name))
      throw std::invalid_argument(fmt::format("{}: channel '{}' given twice", displayName(image_), channel.name));
    names_.push_back(channel.name);
  }
}

bool ImageRows::has(std::string_view name) const {
  return std::find(names_.begin(), names_.end(), name) != names_.end();
}

void ImageRows::checkRows(int first, int count) const {
  if (first < 0 || count < 0 || first > height() - count)
    throw std::out_of_range(
        fmt::format("{}: rows {}..{} of a {}-row image", displayName(image_), first, first + count, height()));
}

std::span<const float> ImageRows::rowsOf(const ImageChannel& channel, int first, int count) const {
  const size_t width = static_cast<size_t>(image_.width());
  return std::span<const float>(channel.data)
      .subspan(width * static_cast<size_t>(first), width * static_cast<size_t>(count));
}

std::span<const float> ImageRows::stored(std::string_view name, int first, int count) const {
  checkRows(first, count);
  const ImageChannel* channel = image_.find(name);
  return channel != nullptr ? rowsOf(*channel, first, count) : std::span<const float>{};
}

void ImageRows::read(std::string_view name, int first, int count, std::span<float> out) const {
  checkRows(first, count);
  const size_t width = static_cast<size_t>(image_.width());
  if (out.size() != width * static_cast<size_t>(count))
    throw std::out_of_range(
        fmt::format("{}: {} values for {} rows of {}", displayName(image_), out.size(), count, image_.width()));
  if (const ImageChannel* channel = image_.find(name)) {
    const std::span<const float> rows = rowsOf(*channel, first, count);
    std::copy(rows.begin(), rows.end(), out.begin());
    return;
  }
  for (const DeferredChannel& channel : deferred_)
    if (channel.name == name) return channel.read(first, count, out);
  throw std::runtime_error(
      fmt::format("{}: no channel '{}' (channels: {})", displayName(image_), name, fmt::join(names_, ", ")));
}

int bandRows(int width, size_t channels, size_t budgetBytes, int multiple) {
  const size_t rowBytes =
      std::max<size_t>(1, static_cast<size_t>(std::max(width, 1)) * std::max<size_t>(channels, 1) * sizeof(float));
  const size_t rows = budgetBytes / rowBytes / static_cast<size_t>(multiple) * static_cast<size_t>(multiple);
  return static_cast<int>(std::clamp<size_t>(rows, static_cast<size_t>(multiple), size_t{1} << 20));
}

}  // namespace penumbra
