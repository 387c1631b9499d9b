// Image: channel bookkeeping (sizes, unique names), lookups with errors that name the image and the
// channel, and row flipping between bottom-up renderer output and top-down file order.
#include "host/io/image.h"

#include <algorithm>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>
#include <fmt/ranges.h>

namespace penumbra {
namespace {

std::string displayName(const std::string& source) { return source.empty() ? "image" : source; }

}  // namespace

Image::Image(int width, int height, std::string source) : width_(width), height_(height), source_(std::move(source)) {
  if (width < 0 || height < 0)
    throw std::invalid_argument(fmt::format("{}: invalid image size {}x{}", displayName(source_), width, height));
}

std::vector<std::string> Image::channelNames() const {
  std::vector<std::string> names;
  names.reserve(channels_.size());
  for (const ImageChannel& channel : channels_) names.push_back(channel.name);
  return names;
}

void Image::add(std::string name, std::vector<float> data) {
  if (name.empty()) throw std::invalid_argument(fmt::format("{}: channel name is empty", displayName(source_)));
  if (find(name) != nullptr)
    throw std::invalid_argument(fmt::format("{}: channel '{}' added twice", displayName(source_), name));
  if (data.size() != pixelCount())
    throw std::invalid_argument(fmt::format("{}: channel '{}' has {} values, expected {} ({}x{})", displayName(source_),
                                            name, data.size(), pixelCount(), width_, height_));
  channels_.push_back({std::move(name), std::move(data)});
}

void Image::addFilled(std::string name, float value) { add(std::move(name), std::vector<float>(pixelCount(), value)); }

const ImageChannel* Image::find(std::string_view name) const {
  auto it = std::find_if(channels_.begin(), channels_.end(),
                         [&](const ImageChannel& channel) { return channel.name == name; });
  return it == channels_.end() ? nullptr : &*it;
}

ImageChannel* Image::find(std::string_view name) { return const_cast<ImageChannel*>(std::as_const(*this).find(name)); }

const ImageChannel& Image::require(std::string_view name) const {
  if (const ImageChannel* channel = find(name)) return *channel;
  const std::vector<std::string> names = channelNames();
  throw std::runtime_error(fmt::format("{}: no channel '{}' (channels: {})", displayName(source_), name,
                                       names.empty() ? "none" : fmt::format("{}", fmt::join(names, ", "))));
}

void Image::flipRows() {
  for (ImageChannel& channel : channels_) penumbra::flipRows(channel.data, width_, height_);
}

void flipRows(std::span<float> data, int width, int height) {
  if (width < 0 || height < 0 || data.size() != static_cast<size_t>(width) * static_cast<size_t>(height))
    throw std::invalid_argument(fmt::format("flipRows: {} values for a {}x{} plane", data.size(), width, height));
  const size_t rowLength = static_cast<size_t>(width);
  for (int top = 0, bottom = height - 1; top < bottom; ++top, --bottom)
    std::swap_ranges(data.begin() + static_cast<std::ptrdiff_t>(top * rowLength),
                     data.begin() + static_cast<std::ptrdiff_t>((top + 1) * rowLength),
                     data.begin() + static_cast<std::ptrdiff_t>(bottom * rowLength));
}

}  // namespace penumbra
