// ImageRows: what the EXR and PNG writers read, band by band: an Image's size, header and channels, plus channels
// whose rows are read on demand (a frame's channels straight from its device buffers), so that a picture need never
// be whole on the host (docs/robustness.md: host memory per pixel).
#pragma once

#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "host/io/image.h"

namespace penumbra {

// Rows [first, first + count) of a channel, row 0 at the top, into `out` (count * width values, row by row).
using RowReader = std::function<void(int first, int count, std::span<float> out)>;

struct DeferredChannel {
  std::string name;
  RowReader read;
};

// A view: `image` and the readers must outlive it. Throws std::invalid_argument naming the image when a deferred
// channel's name is empty, is given twice or is one of the image's own.
class ImageRows {
 public:
  explicit ImageRows(const Image& image, std::span<const DeferredChannel> deferred = {});

  const Image& header() const { return image_; }  // size, attributes, numbers, matrices
  int width() const { return image_.width(); }
  int height() const { return image_.height(); }
  bool empty() const { return image_.empty(); }
  // The image's channels in their order, then the deferred ones.
  const std::vector<std::string>& channelNames() const { return names_; }
  bool has(std::string_view name) const;

  // Rows [first, first + count) of channel `name` into out (count * width values). Throws std::runtime_error naming
  // the image, the channel and the channels it has when `name` is absent, and std::out_of_range for rows outside the
  // image or an `out` of another size.
  void read(std::string_view name, int first, int count, std::span<float> out) const;
  // Rows [first, first + count) of a channel the image holds, in place (no copy); empty for a deferred channel, which
  // only read() can produce. Range checks as read()'s.
  std::span<const float> stored(std::string_view name, int first, int count) const;

 private:
  void checkRows(int first, int count) const;  // throws std::out_of_range for rows outside the image
  std::span<const float> rowsOf(const ImageChannel& channel, int first, int count) const;  // rows checked

  const Image& image_;
  std::span<const DeferredChannel> deferred_;
  std::vector<std::string> names_;
};

// Rows per band for streaming `channels` channels of `width` floats within about `budgetBytes`, a multiple of
// `multiple` rows (OpenEXR's ZIP blocks are 16 rows), at least `multiple`.
int bandRows(int width, size_t channels, size_t budgetBytes = size_t{32} << 20, int multiple = 16);

}  // namespace penumbra
