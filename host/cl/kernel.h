// One typed wrapper per kernel launch: builds (through the context's program cache), sets arguments in
// one place, checks the work-group size and local memory against the device and kernel limits, pads the
// global size up to a multiple of the work-group (kernels bound-check with their real sizes: NVIDIA's
// OpenCL and PoCL 3.1 lack non-uniform work-groups), and reports the launch's event to the profiler.
#pragma once

#include <CL/opencl.hpp>
#include <array>
#include <string>
#include <type_traits>
#include <vector>

#include "host/cl/buffer.h"
#include "host/cl/context.h"
#include "host/cl/error.h"

namespace penumbra {

// A __local argument of `bytes` bytes.
struct LocalMem {
  size_t bytes;
};

// 1-, 2- or 3-D sizes; unused dimensions are 1.
struct Range {
  Range(size_t x) : dims(1), size{x, 1, 1} {}  // NOLINT(google-explicit-constructor): Range r = 256;
  Range(size_t x, size_t y) : dims(2), size{x, y, 1} {}
  Range(size_t x, size_t y, size_t z) : dims(3), size{x, y, z} {}
  size_t count() const { return size[0] * size[1] * size[2]; }
  unsigned dims;
  std::array<size_t, 3> size;
};

inline size_t roundUp(size_t value, size_t multiple) { return (value + multiple - 1) / multiple * multiple; }

class Kernel {
 public:
  // `stage` names the pipeline stage ("raster", "blur", ...) for errors and profiling.
  Kernel(Context& ctx, const std::string& source, const std::string& entry, std::string stage,
         const std::string& options = {});

  template <class... Args>
  Kernel& args(const Args&... values) {
    localBytes_ = 0;
    cl_uint index = 0;
    (setArg(index++, values), ...);
    return *this;
  }

  // The least device memory the next launch must read plus write, in bytes (its bandwidth floor's numerator;
  // each stage documents its formula beside the call). Consumed by launch(); launches without it record 0.
  Kernel& moves(uint64_t bytes) {
    bytesHint_ = bytes;
    return *this;
  }

  // Enqueues over `global` work-items (padded to a multiple of `local` per dimension) and returns the event.
  cl::Event launch(const Range& global, const Range& local, const std::vector<cl::Event>* waitFor = nullptr);

  // The largest work-group this kernel can use on this device (kernel and device limits).
  size_t maxWorkGroupSize() const { return maxWorkGroupSize_; }
  // CL_KERNEL_LOCAL_MEM_SIZE: the __local arrays the kernel declares itself, in bytes.
  uint64_t staticLocalBytes() const { return staticLocalBytes_; }
  // Whether a launch of work-groups of `local` with `dynamicLocalBytes` of __local arguments passes the limit checks
  // (work-group size, item sizes, local memory as DeviceInfo::localMemBytes reports it): what plans with a fallback
  // ask before they choose.
  bool fits(const Range& local, uint64_t dynamicLocalBytes = 0) const;
  const std::string& name() const { return entry_; }
  const std::string& stage() const { return stage_; }
  cl::Kernel& handle() { return kernel_; }

 private:
  template <class T>
  void setArg(cl_uint index, const T& value) {
    cl_int err;
    if constexpr (std::is_same_v<T, LocalMem>) {
      err = kernel_.setArg(index, cl::Local(value.bytes));
      localBytes_ += value.bytes;
    } else if constexpr (requires { value.get(); }) {
      err = kernel_.setArg(index, value.get());  // Buffer<T>
    } else {
      static_assert(std::is_trivially_copyable_v<T>, "kernel arguments are buffers, LocalMem or POD values");
      err = kernel_.setArg(index, sizeof(T), &value);
    }
    checkSetArg(err, index, entry_, stage_);
  }

  void checkLimits(const Range& local) const;

  Context& ctx_;
  std::string entry_, stage_;
  cl::Kernel kernel_;
  size_t maxWorkGroupSize_ = 0;
  uint64_t staticLocalBytes_ = 0;  // CL_KERNEL_LOCAL_MEM_SIZE: __local arrays declared in the kernel
  size_t localBytes_ = 0;          // __local arguments set by args()
  uint64_t bytesHint_ = 0;         // set by moves(), reported with the next launch
};

}  // namespace penumbra
