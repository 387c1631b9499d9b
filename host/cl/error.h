// Errors of the OpenCL runtime: every failing call is reported with the error's name
// (CL_INVALID_WORK_GROUP_SIZE), the call, and the kernel and stage it served; build failures carry the
// device, the options and the whole build log.
#pragma once

#include <CL/cl.h>

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>

namespace penumbra {

// "CL_OUT_OF_RESOURCES" for -5; "CL_UNKNOWN_ERROR(-9999)" for codes this build does not know.
std::string clErrorName(cl_int code);

class ClError : public std::runtime_error {
 public:
  ClError(cl_int code, std::string call, std::string kernel = {}, std::string stage = {});
  cl_int code() const { return code_; }
  const std::string& call() const { return call_; }
  const std::string& kernel() const { return kernel_; }
  const std::string& stage() const { return stage_; }

 private:
  cl_int code_;
  std::string call_, kernel_, stage_;
};

class BuildError : public std::runtime_error {
 public:
  BuildError(std::string source, std::string device, std::string options, std::string log);
  const std::string& log() const { return log_; }

 private:
  std::string log_;
};

// No OpenCL platform/device at all, or none that matches the user's selection. Tools exit with 69
// (EX_UNAVAILABLE) on it.
class NoDeviceError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};
inline constexpr int kExitNoDevice = 69;

// The errors of Buffer's templates, formatted here rather than in every file that instantiates them:
// CL_INVALID_BUFFER_SIZE for `count` elements of `elementBytes` above the device's largest allocation,
// CL_MISALIGNED_SUB_BUFFER_OFFSET for a region starting `offsetBytes` in.
[[noreturn]] void throwBufferTooLarge(size_t count, size_t elementBytes, uint64_t maxAllocBytes);
[[noreturn]] void throwMisalignedRegion(size_t offsetBytes, uint64_t alignBytes);
// clSetKernelArg's failure for argument `index` of `kernel` (Kernel::args).
void checkSetArg(cl_int code, unsigned index, std::string_view kernel, std::string_view stage);

// Throws ClError unless code == CL_SUCCESS.
inline void clCheck(cl_int code, std::string_view call, std::string_view kernel = {}, std::string_view stage = {}) {
  if (code != CL_SUCCESS) throw ClError(code, std::string(call), std::string(kernel), std::string(stage));
}

}  // namespace penumbra
