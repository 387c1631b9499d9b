// Images as callers hold them: float texels at an offset into a buffer, rows a pitch apart, in either row order
// (kernels/shared/caller_inputs.h's CallerImageGpu on the device). Checked against their buffers here, converted by
// the stages that take them (host/pipeline/caller_shade.h), and copied between layouts (copyImage: a stage's input
// packed from the caller's layout, its result unpacked into it).
#pragma once

#include <cstddef>
#include <string>

#include "host/cl/buffer.h"
#include "host/cl/context.h"
#include "kernels/shared/caller_inputs.h"

namespace penumbra {

// One of the caller's images: float texels in `buffer` (the caller's memory, wrapped for the call) starting
// `offsetBytes` in, rows `rowPitchBytes` apart (0: packed), the first row in memory the bottom one unless `topDown`.
// Default-constructed over a buffer: penumbra's own layout (packed rows from the bottom).
struct CallerImage {
  Buffer<float> buffer;
  size_t offsetBytes = 0, rowPitchBytes = 0;
  bool topDown = false;
};

// Where `image`'s width x height texels of `channels` floats lie (CallerImageGpu), checked: offset and pitch multiples
// of 4 bytes, the pitch at least a row, the last texel inside the buffer, float indices within 32 bits. Throws
// std::invalid_argument starting with `what`.
CallerImageGpu imageLayout(const CallerImage& image, int width, int height, int channels, const std::string& what);

// Whether a layout is penumbra's own: packed rows from the bottom at offset 0 (a buffer the stages read in place).
inline bool packedBottomUp(const CallerImageGpu& layout) {
  return layout.offset == 0 && layout.rowPitch == layout.width * layout.channels && !layout.topDown;
}

// Copies width x height texels of `channels` floats from `src`'s layout into `dst`'s (one "layout/caller_copy" pass:
// 8 bytes per float moved). The layouts must have been checked by imageLayout; the images may not overlap.
void copyImage(Context& ctx, const CallerImage& src, const CallerImageGpu& srcLayout, CallerImage& dst,
               const CallerImageGpu& dstLayout);

}  // namespace penumbra
