// Arrays in and out of the Python module's stages: numpy arrays (uploaded into a buffer of the context, straight from
// the array's memory when it already is C-contiguous of the right type; results read into new numpy arrays) or
// pyopencl arrays on the context's own cl_context (used in place: no host copy either way; the stage waits for the
// input's events and its result carries the stage's event, so pyopencl's own operations order after it).
#pragma once

#include <pybind11/numpy.h>

#include <penumbra/penumbra.hpp>
#include <string>
#include <utility>
#include <vector>

namespace penumbra::python {

template <class T>
using Array = pybind11::array_t<T, pybind11::array::c_style | pybind11::array::forcecast>;

// A buffer of the context's, released when the call ends (the stage's commands keep it alive as long as they run).
class DeviceBuffer {
 public:
  DeviceBuffer() = default;
  DeviceBuffer(const Context& ctx, size_t bytes, const void* data = nullptr) {
    cl_int err = CL_SUCCESS;
    const cl_mem_flags flags = CL_MEM_READ_WRITE | (data != nullptr ? CL_MEM_COPY_HOST_PTR : 0);
    mem_ = clCreateBuffer(ctx.clContext(), flags, bytes > 0 ? bytes : 1, const_cast<void*>(data), &err);
    if (err != CL_SUCCESS) throw Error(PN_ERROR_OPENCL, "clCreateBuffer failed (" + std::to_string(err) + ")", err);
  }
  DeviceBuffer(const DeviceBuffer&) = delete;
  DeviceBuffer& operator=(const DeviceBuffer&) = delete;
  DeviceBuffer(DeviceBuffer&& other) noexcept : mem_(other.mem_) { other.mem_ = nullptr; }
  DeviceBuffer& operator=(DeviceBuffer&& other) noexcept {
    std::swap(mem_, other.mem_);
    return *this;
  }
  ~DeviceBuffer() {
    if (mem_ != nullptr) clReleaseMemObject(mem_);
  }
  cl_mem get() const { return mem_; }

 private:
  cl_mem mem_ = nullptr;
};

// Waits for `event` (the stage's, released here), then reads `bytes` of `buffer` into `out`.
inline void download(const Context& ctx, cl_mem buffer, cl_event event, void* out, size_t bytes) {
  const cl_int err = clEnqueueReadBuffer(ctx.clQueue(), buffer, CL_TRUE, 0, bytes, out, 1, &event, nullptr);
  clReleaseEvent(event);
  if (err != CL_SUCCESS) throw Error(PN_ERROR_OPENCL, "clEnqueueReadBuffer failed (" + std::to_string(err) + ")", err);
}

// The event of one stage call: `enqueue(cl_event*)` runs with the GIL released and leaves the stage's event there;
// released with the holder (also when reading a result throws).
class StageEvent {
 public:
  template <class Enqueue>
  explicit StageEvent(Enqueue&& enqueue) {
    pybind11::gil_scoped_release release;
    enqueue(&event_);
  }
  StageEvent(const StageEvent&) = delete;
  StageEvent& operator=(const StageEvent&) = delete;
  ~StageEvent() {
    if (event_ != nullptr) clReleaseEvent(event_);
  }
  cl_event get() const { return event_; }

 private:
  cl_event event_ = nullptr;
};

// (height, width) is one channel, (height, width, channels) several.
ImageShape shapeOf(const std::vector<pybind11::ssize_t>& dims, const char* stage);
inline ImageShape shapeOf(const pybind11::array& image, const char* stage) {
  return shapeOf(std::vector<pybind11::ssize_t>(image.shape(), image.shape() + image.ndim()), stage);
}

// `array` as a C-contiguous array of `dtype` ("float16", ...): itself when it already is one.
inline pybind11::array contiguous(const pybind11::handle& array, const char* dtype) {
  return pybind11::module_::import("numpy").attr("ascontiguousarray")(array, pybind11::arg("dtype") = dtype);
}

// True for a pyopencl.array.Array.
bool isDeviceArray(const pybind11::handle& object);

// An OpenCL handle given as an integer or as a pyopencl object (its int_ptr); `what` names it in the TypeError.
uintptr_t clHandle(const pybind11::handle& object, const char* what);

// One array argument of a stage, on the device: a pyopencl array of `dtype`, C-contiguous with no offset, on the
// context's cl_context, used in place; else anything numpy takes, converted to a C-contiguous `dtype` array and
// uploaded (zero-copy on the host where it already is one). `stage` and `name` name it in errors (ValueError).
class ArrayIn {
 public:
  ArrayIn(const Context& ctx, const pybind11::handle& object, const char* dtype, const char* stage, const char* name);
  cl_mem mem() const { return device_ ? deviceMem_ : buffer_.get(); }
  const std::vector<pybind11::ssize_t>& shape() const { return shape_; }
  bool onDevice() const { return device_; }
  const pybind11::object& queue() const { return queue_; }  // the pyopencl array's queue (device only)
  // The pyopencl array's pending events (retained for the call; device only), the stage's wait list.
  const std::vector<cl_event>& waits() const { return waits_; }
  ArrayIn(const ArrayIn&) = delete;
  ArrayIn& operator=(const ArrayIn&) = delete;
  ~ArrayIn();

 private:
  bool device_ = false;
  pybind11::object array_, queue_;
  cl_mem deviceMem_ = nullptr;
  DeviceBuffer buffer_;
  std::vector<pybind11::ssize_t> shape_;
  std::vector<cl_event> waits_;
};

// A result of `dims` elements of `dtype`, where the input `like` lives: a new pyopencl array on its queue, written in
// place, or a device buffer read into a new numpy array when the stage's event completes. `into` (not None): the
// caller's own memory to write instead, a pyopencl array of that shape and dtype (as ArrayIn takes them) or a
// pyopencl Buffer of at least that many bytes on the context's cl_context (a pyopencl input's queue then carries it);
// the stage waits for the array's pending events too (waits()). `stage` names it in errors.
class ArrayOut {
 public:
  ArrayOut(const Context& ctx, const ArrayIn& like, const std::vector<pybind11::ssize_t>& dims, const char* dtype,
           const pybind11::handle& into = pybind11::none(), const char* stage = "");
  cl_mem mem() const { return device_ ? deviceMem_ : buffer_.get(); }
  size_t bytes() const { return bytes_; }
  // The stage's wait list: the input's pending events and those of the caller's array written into.
  std::vector<cl_event> waits(const ArrayIn& in) const;
  // The array, once the stage has enqueued with `event` (retained here as needed; the caller keeps its reference):
  // numpy arrays are read (waiting for it), pyopencl arrays get it among their events.
  pybind11::object finish(cl_event event);
  ArrayOut(const ArrayOut&) = delete;
  ArrayOut& operator=(const ArrayOut&) = delete;
  ~ArrayOut();

 private:
  const Context& ctx_;
  bool device_ = false;
  pybind11::object array_;
  cl_mem deviceMem_ = nullptr;
  DeviceBuffer buffer_;
  size_t bytes_ = 0;
  std::vector<cl_event> waits_;
};

}  // namespace penumbra::python
