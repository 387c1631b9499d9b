// The device's measured copy bandwidth: a timed clEnqueueCopyBuffer of a large buffer (OpenCL profiling events),
// the denominator of bench's bandwidth floors. A copy reads and writes every byte, so it moves 2 x size bytes.
#pragma once

#include <cstddef>

#include "host/cl/context.h"

namespace penumbra {

struct CopyBandwidth {
  size_t bufferBytes = 0;     // size of the copied buffer
  double medianMs = 0;        // median device time of one copy
  double bytesPerSecond = 0;  // 2 * bufferBytes / median time
  int repeats = 0;
};

// One untimed copy, then `repeats` timed ones. The buffer is `bytes` capped at a quarter of the device's maximum
// allocation (two buffers live at once). Does not touch the context's profiler.
CopyBandwidth measureCopyBandwidth(Context& ctx, size_t bytes = size_t{256} << 20, int repeats = 5);

}  // namespace penumbra
