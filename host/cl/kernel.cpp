// Kernel launch checks: limits are checked on the host so a bad configuration fails with a message that
// names the kernel and the limit, not an opaque CL_INVALID_WORK_GROUP_SIZE from the driver.
#include "host/cl/kernel.h"

#include <utility>

namespace penumbra {

Kernel::Kernel(Context& ctx, const std::string& source, const std::string& entry, std::string stage,
               const std::string& options)
    : ctx_(ctx), entry_(entry), stage_(std::move(stage)) {
  cl_int err = CL_SUCCESS;
  kernel_ = cl::Kernel(ctx.program(source, options), entry.c_str(), &err);
  clCheck(err, "clCreateKernel", entry_, stage_);
  clCheck(kernel_.getWorkGroupInfo(ctx.device(), CL_KERNEL_WORK_GROUP_SIZE, &maxWorkGroupSize_),
          "clGetKernelWorkGroupInfo", entry_, stage_);
  cl_ulong staticLocal = 0;
  clCheck(kernel_.getWorkGroupInfo(ctx.device(), CL_KERNEL_LOCAL_MEM_SIZE, &staticLocal), "clGetKernelWorkGroupInfo",
          entry_, stage_);
  staticLocalBytes_ = staticLocal;
}

void Kernel::checkLimits(const Range& local) const {
  const DeviceInfo& info = ctx_.info();
  if (local.count() == 0) throw ClError(CL_INVALID_WORK_GROUP_SIZE, "launch (empty work-group)", entry_, stage_);
  if (local.count() > maxWorkGroupSize_)
    throw ClError(CL_INVALID_WORK_GROUP_SIZE,
                  fmt::format("launch (work-group of {} > kernel limit {})", local.count(), maxWorkGroupSize_), entry_,
                  stage_);
  for (unsigned d = 0; d < local.dims; ++d)
    if (local.size[d] > info.maxWorkItemSizes[d])
      throw ClError(CL_INVALID_WORK_ITEM_SIZE,
                    fmt::format("launch (work-group dimension {} is {} > device limit {})", d, local.size[d],
                                info.maxWorkItemSizes[d]),
                    entry_, stage_);
  if (staticLocalBytes_ + localBytes_ > info.localMemBytes)
    throw ClError(CL_OUT_OF_RESOURCES,
                  fmt::format("launch (local memory {} + {} bytes > device limit {})", staticLocalBytes_, localBytes_,
                              info.localMemBytes),
                  entry_, stage_);
}

bool Kernel::fits(const Range& local, uint64_t dynamicLocalBytes) const {
  const DeviceInfo& info = ctx_.info();
  if (local.count() == 0 || local.count() > maxWorkGroupSize_) return false;
  for (unsigned d = 0; d < local.dims; ++d)
    if (local.size[d] > info.maxWorkItemSizes[d]) return false;
  return staticLocalBytes_ + dynamicLocalBytes <= info.localMemBytes;
}

cl::Event Kernel::launch(const Range& global, const Range& local, const std::vector<cl::Event>* waitFor) {
  if (global.dims != local.dims)
    throw ClError(CL_INVALID_WORK_DIMENSION, "launch (global and local ranges differ in dimensions)", entry_, stage_);
  checkLimits(local);
  const uint64_t bytes = std::exchange(bytesHint_, 0);
  cl::Event event;
  if (global.count() == 0) {  // nothing to do: still return a completed event so callers can wait on it
    cl_int err = CL_SUCCESS;
    cl::UserEvent done(ctx_.context(), &err);
    clCheck(err, "clCreateUserEvent", entry_, stage_);
    done.setStatus(CL_COMPLETE);
    return done;
  }
  std::array<size_t, 3> padded{};
  for (unsigned d = 0; d < 3; ++d) padded[d] = roundUp(global.size[d], local.size[d]);
  const cl::NDRange globalRange = global.dims == 1   ? cl::NDRange(padded[0])
                                  : global.dims == 2 ? cl::NDRange(padded[0], padded[1])
                                                     : cl::NDRange(padded[0], padded[1], padded[2]);
  const cl::NDRange localRange = local.dims == 1   ? cl::NDRange(local.size[0])
                                 : local.dims == 2 ? cl::NDRange(local.size[0], local.size[1])
                                                   : cl::NDRange(local.size[0], local.size[1], local.size[2]);
  clCheck(ctx_.queue().enqueueNDRangeKernel(kernel_, cl::NullRange, globalRange, localRange, waitFor, &event),
          "clEnqueueNDRangeKernel", entry_, stage_);
  if (ctx_.profiler() != nullptr) ctx_.profiler()->record(stage_ + "/" + entry_, event, bytes);
  return event;
}

}  // namespace penumbra
