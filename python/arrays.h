// numpy arrays to and from the context's device buffers, for the Python module's stages: a buffer created from an
// array's own memory (C-contiguous arrays of the right type are not copied on the host), a read into a new array.
#pragma once

#include <pybind11/numpy.h>

#include <penumbra/penumbra.hpp>
#include <string>

namespace penumbra::python {

template <class T>
using Array = pybind11::array_t<T, pybind11::array::c_style | pybind11::array::forcecast>;

// A buffer of the context's, released when the call ends (the stage's commands keep it alive as long as they run).
class DeviceBuffer {
 public:
  DeviceBuffer(const Context& ctx, size_t bytes, const void* data = nullptr) {
    cl_int err = CL_SUCCESS;
    const cl_mem_flags flags = CL_MEM_READ_WRITE | (data != nullptr ? CL_MEM_COPY_HOST_PTR : 0);
    mem_ = clCreateBuffer(ctx.clContext(), flags, bytes > 0 ? bytes : 1, const_cast<void*>(data), &err);
    if (err != CL_SUCCESS) throw Error(PN_ERROR_OPENCL, "clCreateBuffer failed (" + std::to_string(err) + ")", err);
  }
  DeviceBuffer(const DeviceBuffer&) = delete;
  DeviceBuffer& operator=(const DeviceBuffer&) = delete;
  ~DeviceBuffer() { clReleaseMemObject(mem_); }
  cl_mem get() const { return mem_; }

 private:
  cl_mem mem_ = nullptr;
};

// Waits for `event` (the stage's, released here), then reads `bytes` of `buffer` into `out`.
inline void download(const Context& ctx, const DeviceBuffer& buffer, cl_event event, void* out, size_t bytes) {
  const cl_int err = clEnqueueReadBuffer(ctx.clQueue(), buffer.get(), CL_TRUE, 0, bytes, out, 1, &event, nullptr);
  clReleaseEvent(event);
  if (err != CL_SUCCESS) throw Error(PN_ERROR_OPENCL, "clEnqueueReadBuffer failed (" + std::to_string(err) + ")", err);
}

// (height, width) is one channel, (height, width, channels) several.
inline ImageShape shapeOf(const pybind11::array& image, const char* stage) {
  if (image.ndim() != 2 && image.ndim() != 3)
    throw pybind11::value_error(std::string(stage) + ": an image is (height, width) or (height, width, channels)");
  return {static_cast<uint32_t>(image.shape(1)), static_cast<uint32_t>(image.shape(0)),
          image.ndim() == 3 ? static_cast<uint32_t>(image.shape(2)) : 1u};
}

// `array` as a C-contiguous array of `dtype` ("float16", ...): itself when it already is one.
inline pybind11::array contiguous(const pybind11::handle& array, const char* dtype) {
  return pybind11::module_::import("numpy").attr("ascontiguousarray")(array, pybind11::arg("dtype") = dtype);
}

}  // namespace penumbra::python
