// Copy bandwidth from profiling events of clEnqueueCopyBuffer between two device buffers.
#include "tools/eval/bandwidth.h"

#include <algorithm>
#include <vector>

#include "host/cl/error.h"
#include "tools/eval/bench_stats.h"

namespace penumbra {

CopyBandwidth measureCopyBandwidth(Context& ctx, size_t bytes, int repeats) {
  CopyBandwidth result;
  result.bufferBytes = std::max<size_t>(std::min<size_t>(bytes, ctx.info().maxAllocBytes / 4) / 16 * 16, 16);
  result.repeats = std::max(repeats, 1);
  cl_int err = CL_SUCCESS;
  cl::Buffer src(ctx.context(), CL_MEM_READ_WRITE, result.bufferBytes, nullptr, &err);
  clCheck(err, "clCreateBuffer", "copy", "bandwidth");
  cl::Buffer dst(ctx.context(), CL_MEM_READ_WRITE, result.bufferBytes, nullptr, &err);
  clCheck(err, "clCreateBuffer", "copy", "bandwidth");
  // Touch both buffers first so first-use page faults and lazy allocation stay out of the timed copies.
  clCheck(ctx.queue().enqueueFillBuffer(src, cl_uint{0x3f800000}, 0, result.bufferBytes), "clEnqueueFillBuffer", "copy",
          "bandwidth");
  clCheck(ctx.queue().enqueueFillBuffer(dst, cl_uint{0}, 0, result.bufferBytes), "clEnqueueFillBuffer", "copy",
          "bandwidth");
  std::vector<double> times;
  for (int i = 0; i <= result.repeats; ++i) {
    cl::Event event;
    clCheck(ctx.queue().enqueueCopyBuffer(src, dst, 0, 0, result.bufferBytes, nullptr, &event), "clEnqueueCopyBuffer",
            "copy", "bandwidth");
    clCheck(event.wait(), "clWaitForEvents", "copy", "bandwidth");
    cl_ulong start = 0, end = 0;
    clCheck(event.getProfilingInfo(CL_PROFILING_COMMAND_START, &start), "clGetEventProfilingInfo", "copy", "bandwidth");
    clCheck(event.getProfilingInfo(CL_PROFILING_COMMAND_END, &end), "clGetEventProfilingInfo", "copy", "bandwidth");
    if (i > 0) times.push_back(end > start ? static_cast<double>(end - start) * 1e-6 : 0.0);
  }
  result.medianMs = median(times);
  if (result.medianMs > 0)
    result.bytesPerSecond = 2.0 * static_cast<double>(result.bufferBytes) / (result.medianMs * 1e-3);
  return result;
}

}  // namespace penumbra
