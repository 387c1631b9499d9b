// The caller's own OpenCL objects, made with the plain OpenCL C API as an application would make them (never through
// penumbra), and their reference counts: what the interop tests hand to penumbra and check afterwards.
#pragma once

#include <CL/cl.h>
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

namespace penumbra::test {

// The device penumbra's own contexts take for PENUMBRA_DEVICE "cpu" (scripts/test.sh) or "gpu", or unset (auto: the
// first GPU, else the first CPU), so that frames on the test's objects and on penumbra's own can be compared.
inline cl_device_id callerDevice() {
  const char* env = std::getenv("PENUMBRA_DEVICE");
  const std::string spec = env != nullptr ? env : "";
  std::vector<cl_device_type> order = {CL_DEVICE_TYPE_GPU, CL_DEVICE_TYPE_CPU};
  if (spec == "cpu") order = {CL_DEVICE_TYPE_CPU};
  if (spec == "gpu") order = {CL_DEVICE_TYPE_GPU};
  order.push_back(CL_DEVICE_TYPE_ALL);
  cl_uint count = 0;
  clGetPlatformIDs(0, nullptr, &count);
  std::vector<cl_platform_id> platforms(count);
  clGetPlatformIDs(count, platforms.data(), nullptr);
  for (cl_device_type type : order)
    for (cl_platform_id platform : platforms) {
      cl_device_id device = nullptr;
      if (clGetDeviceIDs(platform, type, 1, &device, nullptr) == CL_SUCCESS) return device;
    }
  return nullptr;
}

// A context and an in-order queue (no profiling: penumbra must not need it) of the caller's.
struct CallerCl {
  cl_device_id device = nullptr;
  cl_context context = nullptr;
  cl_command_queue queue = nullptr;

  explicit CallerCl(cl_command_queue_properties properties = 0) : device(callerDevice()) {
    cl_int err = CL_SUCCESS;
    context = clCreateContext(nullptr, 1, &device, nullptr, nullptr, &err);
    EXPECT_EQ(err, CL_SUCCESS);
    queue = clCreateCommandQueue(context, device, properties, &err);
    EXPECT_EQ(err, CL_SUCCESS);
  }
  CallerCl(const CallerCl&) = delete;
  CallerCl& operator=(const CallerCl&) = delete;
  ~CallerCl() {
    clReleaseCommandQueue(queue);
    clReleaseContext(context);
  }

  // A buffer of `count` elements of T, holding `data` (or `fill` in every element).
  template <class T>
  cl_mem buffer(size_t count, const T* data = nullptr, T fill = T{}) const {
    std::vector<T> init(count, fill);
    if (data != nullptr) init.assign(data, data + count);
    cl_int err = CL_SUCCESS;
    cl_mem mem = clCreateBuffer(context, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR,
                                std::max<size_t>(count, 1) * sizeof(T), init.empty() ? nullptr : init.data(), &err);
    EXPECT_EQ(err, CL_SUCCESS);
    return mem;
  }
  template <class T>
  cl_mem buffer(const std::vector<T>& data) const {
    return buffer<T>(data.size(), data.data());
  }

  // Reads `count` elements on the caller's queue (a blocking read: the caller waits on its own queue).
  template <class T>
  std::vector<T> read(cl_mem mem, size_t count) const {
    std::vector<T> out(count);
    EXPECT_EQ(clEnqueueReadBuffer(queue, mem, CL_TRUE, 0, count * sizeof(T), out.data(), 0, nullptr, nullptr),
              CL_SUCCESS);
    return out;
  }
};

inline cl_uint references(cl_context c) {
  cl_uint n = 0;
  clGetContextInfo(c, CL_CONTEXT_REFERENCE_COUNT, sizeof(n), &n, nullptr);
  return n;
}
inline cl_uint references(cl_command_queue q) {
  cl_uint n = 0;
  clGetCommandQueueInfo(q, CL_QUEUE_REFERENCE_COUNT, sizeof(n), &n, nullptr);
  return n;
}
inline cl_uint references(cl_mem m) {
  cl_uint n = 0;
  clGetMemObjectInfo(m, CL_MEM_REFERENCE_COUNT, sizeof(n), &n, nullptr);
  return n;
}
inline cl_uint references(cl_event e) {
  cl_uint n = 0;
  clGetEventInfo(e, CL_EVENT_REFERENCE_COUNT, sizeof(n), &n, nullptr);
  return n;
}

// The reference count of `object` once it has settled at `expected`, or whatever it is after 2 s: PoCL drops its own
// references to a completed command's event and buffers on its worker thread, a moment after clFinish returns (a
// count penumbra kept would never settle).
template <class Object>
cl_uint settled(Object object, cl_uint expected) {
  for (int i = 0; i < 200 && references(object) != expected; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  return references(object);
}

// Fails the test with the library's message unless `status` is PN_SUCCESS.
#define PN_ASSERT_OK(call)                                                                          \
  do {                                                                                              \
    const pn_status pnStatus = (call);                                                              \
    ASSERT_EQ(pnStatus, PN_SUCCESS) << pn_status_name(pnStatus) << ": " << pn_last_error_message(); \
  } while (0)

}  // namespace penumbra::test
