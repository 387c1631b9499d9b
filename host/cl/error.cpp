// Names of OpenCL error codes (OpenCL 3.0 cl.h) and the messages of the runtime's exceptions.
#include "host/cl/error.h"

#include <fmt/format.h>

namespace penumbra {

std::string clErrorName(cl_int code) {
  switch (code) {
#define PENUMBRA_CL_ERROR(name) \
  case name:                    \
    return #name;
    PENUMBRA_CL_ERROR(CL_SUCCESS)
    PENUMBRA_CL_ERROR(CL_DEVICE_NOT_FOUND)
    PENUMBRA_CL_ERROR(CL_DEVICE_NOT_AVAILABLE)
    PENUMBRA_CL_ERROR(CL_COMPILER_NOT_AVAILABLE)
    PENUMBRA_CL_ERROR(CL_MEM_OBJECT_ALLOCATION_FAILURE)
    PENUMBRA_CL_ERROR(CL_OUT_OF_RESOURCES)
    PENUMBRA_CL_ERROR(CL_OUT_OF_HOST_MEMORY)
    PENUMBRA_CL_ERROR(CL_PROFILING_INFO_NOT_AVAILABLE)
    PENUMBRA_CL_ERROR(CL_MEM_COPY_OVERLAP)
    PENUMBRA_CL_ERROR(CL_IMAGE_FORMAT_MISMATCH)
    PENUMBRA_CL_ERROR(CL_IMAGE_FORMAT_NOT_SUPPORTED)
    PENUMBRA_CL_ERROR(CL_BUILD_PROGRAM_FAILURE)
    PENUMBRA_CL_ERROR(CL_MAP_FAILURE)
    PENUMBRA_CL_ERROR(CL_MISALIGNED_SUB_BUFFER_OFFSET)
    PENUMBRA_CL_ERROR(CL_EXEC_STATUS_ERROR_FOR_EVENTS_IN_WAIT_LIST)
    PENUMBRA_CL_ERROR(CL_COMPILE_PROGRAM_FAILURE)
    PENUMBRA_CL_ERROR(CL_LINKER_NOT_AVAILABLE)
    PENUMBRA_CL_ERROR(CL_LINK_PROGRAM_FAILURE)
    PENUMBRA_CL_ERROR(CL_DEVICE_PARTITION_FAILED)
    PENUMBRA_CL_ERROR(CL_KERNEL_ARG_INFO_NOT_AVAILABLE)
    PENUMBRA_CL_ERROR(CL_INVALID_VALUE)
    PENUMBRA_CL_ERROR(CL_INVALID_DEVICE_TYPE)
    PENUMBRA_CL_ERROR(CL_INVALID_PLATFORM)
    PENUMBRA_CL_ERROR(CL_INVALID_DEVICE)
    PENUMBRA_CL_ERROR(CL_INVALID_CONTEXT)
    PENUMBRA_CL_ERROR(CL_INVALID_QUEUE_PROPERTIES)
    PENUMBRA_CL_ERROR(CL_INVALID_COMMAND_QUEUE)
    PENUMBRA_CL_ERROR(CL_INVALID_HOST_PTR)
    PENUMBRA_CL_ERROR(CL_INVALID_MEM_OBJECT)
    PENUMBRA_CL_ERROR(CL_INVALID_IMAGE_FORMAT_DESCRIPTOR)
    PENUMBRA_CL_ERROR(CL_INVALID_IMAGE_SIZE)
    PENUMBRA_CL_ERROR(CL_INVALID_SAMPLER)
    PENUMBRA_CL_ERROR(CL_INVALID_BINARY)
    PENUMBRA_CL_ERROR(CL_INVALID_BUILD_OPTIONS)
    PENUMBRA_CL_ERROR(CL_INVALID_PROGRAM)
    PENUMBRA_CL_ERROR(CL_INVALID_PROGRAM_EXECUTABLE)
    PENUMBRA_CL_ERROR(CL_INVALID_KERNEL_NAME)
    PENUMBRA_CL_ERROR(CL_INVALID_KERNEL_DEFINITION)
    PENUMBRA_CL_ERROR(CL_INVALID_KERNEL)
    PENUMBRA_CL_ERROR(CL_INVALID_ARG_INDEX)
    PENUMBRA_CL_ERROR(CL_INVALID_ARG_VALUE)
    PENUMBRA_CL_ERROR(CL_INVALID_ARG_SIZE)
    PENUMBRA_CL_ERROR(CL_INVALID_KERNEL_ARGS)
    PENUMBRA_CL_ERROR(CL_INVALID_WORK_DIMENSION)
    PENUMBRA_CL_ERROR(CL_INVALID_WORK_GROUP_SIZE)
    PENUMBRA_CL_ERROR(CL_INVALID_WORK_ITEM_SIZE)
    PENUMBRA_CL_ERROR(CL_INVALID_GLOBAL_OFFSET)
    PENUMBRA_CL_ERROR(CL_INVALID_EVENT_WAIT_LIST)
    PENUMBRA_CL_ERROR(CL_INVALID_EVENT)
    PENUMBRA_CL_ERROR(CL_INVALID_OPERATION)
    PENUMBRA_CL_ERROR(CL_INVALID_GL_OBJECT)
    PENUMBRA_CL_ERROR(CL_INVALID_BUFFER_SIZE)
    PENUMBRA_CL_ERROR(CL_INVALID_MIP_LEVEL)
    PENUMBRA_CL_ERROR(CL_INVALID_GLOBAL_WORK_SIZE)
    PENUMBRA_CL_ERROR(CL_INVALID_PROPERTY)
    PENUMBRA_CL_ERROR(CL_INVALID_IMAGE_DESCRIPTOR)
    PENUMBRA_CL_ERROR(CL_INVALID_COMPILER_OPTIONS)
    PENUMBRA_CL_ERROR(CL_INVALID_LINKER_OPTIONS)
    PENUMBRA_CL_ERROR(CL_INVALID_DEVICE_PARTITION_COUNT)
    PENUMBRA_CL_ERROR(CL_INVALID_PIPE_SIZE)
    PENUMBRA_CL_ERROR(CL_INVALID_DEVICE_QUEUE)
    PENUMBRA_CL_ERROR(CL_INVALID_SPEC_ID)
    PENUMBRA_CL_ERROR(CL_MAX_SIZE_RESTRICTION_EXCEEDED)
#undef PENUMBRA_CL_ERROR
    case -1001:
      return "CL_PLATFORM_NOT_FOUND_KHR";
    default:
      return fmt::format("CL_UNKNOWN_ERROR({})", code);
  }
}

namespace {

std::string describe(cl_int code, const std::string& call, const std::string& kernel, const std::string& stage) {
  std::string where;
  if (!stage.empty()) where += fmt::format(" in stage '{}'", stage);
  if (!kernel.empty()) where += fmt::format(" (kernel '{}')", kernel);
  return fmt::format("OpenCL error {} from {}{}", clErrorName(code), call, where);
}

}  // namespace

ClError::ClError(cl_int code, std::string call, std::string kernel, std::string stage)
    : std::runtime_error(describe(code, call, kernel, stage)),
      code_(code),
      call_(std::move(call)),
      kernel_(std::move(kernel)),
      stage_(std::move(stage)) {}

BuildError::BuildError(std::string source, std::string device, std::string options, std::string log)
    : std::runtime_error(
          fmt::format("OpenCL build of '{}' failed on '{}' with options '{}':\n{}", source, device, options, log)),
      log_(std::move(log)) {}

void throwBufferTooLarge(size_t count, size_t elementBytes, uint64_t maxAllocBytes) {
  throw ClError(CL_INVALID_BUFFER_SIZE,
                fmt::format("clCreateBuffer({} bytes, device max alloc {} bytes)", count * elementBytes, maxAllocBytes));
}

void throwMisalignedRegion(size_t offsetBytes, uint64_t alignBytes) {
  throw ClError(CL_MISALIGNED_SUB_BUFFER_OFFSET,
                fmt::format("clCreateSubBuffer(offset {} bytes, device alignment {} bytes)", offsetBytes, alignBytes));
}

void checkSetArg(cl_int code, unsigned index, std::string_view kernel, std::string_view stage) {
  if (code != CL_SUCCESS) throw ClError(code, fmt::format("clSetKernelArg({})", index), std::string(kernel),
                                        std::string(stage));
}

}  // namespace penumbra
