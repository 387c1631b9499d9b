// Images in the caller's layouts: the checks, and the copy between two layouts (kernels/caller_inputs.cl).
#include "host/stages/image_layout.h"

#include <fmt/format.h>

#include <cstdint>
#include <limits>
#include <stdexcept>

#include "host/cl/kernel.h"

namespace penumbra {

CallerImageGpu imageLayout(const CallerImage& image, int width, int height, int channels, const std::string& what) {
  const size_t texelBytes = sizeof(float) * static_cast<size_t>(channels);
  const size_t rowBytes = texelBytes * static_cast<size_t>(width);
  const size_t pitch = image.rowPitchBytes == 0 ? rowBytes : image.rowPitchBytes;
  if (image.offsetBytes % sizeof(float) != 0 || pitch % sizeof(float) != 0)
    throw std::invalid_argument(fmt::format("{}: offset {} and row pitch {} must be multiples of 4 bytes", what,
                                            image.offsetBytes, image.rowPitchBytes));
  if (pitch < rowBytes)
    throw std::invalid_argument(fmt::format("{}: row pitch {} bytes is shorter than a row of {} texels of {} bytes",
                                            what, pitch, width, texelBytes));
  const size_t bufferBytes = image.buffer.bytes();
  const size_t endBytes = image.offsetBytes + pitch * (static_cast<size_t>(height) - 1) + rowBytes;
  if (endBytes > bufferBytes)
    throw std::invalid_argument(
        fmt::format("{}: {}x{} texels of {} bytes at offset {} with row pitch {} end at byte "
                    "{}, past the buffer's {} bytes",
                    what, width, height, texelBytes, image.offsetBytes, pitch, endBytes, bufferBytes));
  if (endBytes / sizeof(float) > std::numeric_limits<uint32_t>::max())
    throw std::invalid_argument(fmt::format("{}: texels past the first 16 GiB of a buffer are not addressed", what));
  CallerImageGpu gpu{};
  gpu.offset = static_cast<uint32_t>(image.offsetBytes / sizeof(float));
  gpu.rowPitch = static_cast<uint32_t>(pitch / sizeof(float));
  gpu.width = static_cast<uint32_t>(width);
  gpu.height = static_cast<uint32_t>(height);
  gpu.channels = static_cast<uint32_t>(channels);
  gpu.topDown = image.topDown ? 1 : 0;
  return gpu;
}

void copyImage(Context& ctx, const CallerImage& src, const CallerImageGpu& srcLayout, CallerImage& dst,
               const CallerImageGpu& dstLayout) {
  if (srcLayout.width != dstLayout.width || srcLayout.height != dstLayout.height ||
      srcLayout.channels != dstLayout.channels)
    throw std::logic_error("copyImage: the two layouts are of different images");
  const uint64_t texels = uint64_t{srcLayout.width} * srcLayout.height;
  Kernel kernel(ctx, "kernels/caller_inputs.cl", "caller_copy", "layout");
  kernel.args(src.buffer, srcLayout, dst.buffer, dstLayout)
      .moves(texels * srcLayout.channels * 2 * sizeof(float))
      .launch(texels, 64);
}

}  // namespace penumbra
