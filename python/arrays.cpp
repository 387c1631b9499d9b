// numpy and pyopencl arrays for the Python module's stages (arrays.h). pyopencl is optional: an object is a pyopencl
// array only when pyopencl.array is already imported (whoever made one imported it), so the module never imports it.
#include "python/arrays.h"

#include <functional>
#include <numeric>

namespace py = pybind11;

namespace penumbra::python {

ImageShape shapeOf(const std::vector<py::ssize_t>& dims, const char* stage) {
  if (dims.size() != 2 && dims.size() != 3)
    throw py::value_error(std::string(stage) + ": an image is (height, width) or (height, width, channels)");
  return {static_cast<uint32_t>(dims[1]), static_cast<uint32_t>(dims[0]),
          dims.size() == 3 ? static_cast<uint32_t>(dims[2]) : 1u};
}

bool isDeviceArray(const py::handle& object) {
  const py::dict modules = py::module_::import("sys").attr("modules");
  return modules.contains("pyopencl.array") && py::isinstance(object, modules["pyopencl.array"].attr("Array"));
}

uintptr_t clHandle(const py::handle& object, const char* what) {
  if (py::isinstance<py::int_>(object)) return object.cast<uintptr_t>();
  if (py::hasattr(object, "int_ptr")) return object.attr("int_ptr").cast<uintptr_t>();
  throw py::type_error(std::string(what) + ": an integer handle or a pyopencl object (with int_ptr), not " +
                       py::str(py::type::of(object)).cast<std::string>());
}

namespace {

size_t byteCount(const std::vector<py::ssize_t>& dims, const char* dtype) {
  const size_t items = std::accumulate(dims.begin(), dims.end(), size_t{1}, std::multiplies<>());
  return items * py::dtype(dtype).itemsize();
}

std::string where(const char* stage, const char* name) { return std::string(stage) + ": " + name; }

}  // namespace

ArrayIn::ArrayIn(const Context& ctx, const py::handle& object, const char* dtype, const char* stage, const char* name) {
  if (!isDeviceArray(object)) {
    const py::array host = contiguous(object, dtype);
    array_ = host;
    shape_.assign(host.shape(), host.shape() + host.ndim());
    const size_t bytes = size_t(host.nbytes());
    buffer_ = DeviceBuffer(ctx, bytes, bytes > 0 ? host.data() : nullptr);
    return;
  }
  device_ = true;
  array_ = py::reinterpret_borrow<py::object>(object);
  if (!py::dtype(dtype).equal(array_.attr("dtype")))
    throw py::value_error(where(stage, name) + " is a pyopencl array of " +
                          py::str(array_.attr("dtype")).cast<std::string>() + ", not " + dtype +
                          " (astype() makes one)");
  if (!array_.attr("flags").attr("c_contiguous").cast<bool>())
    throw py::value_error(where(stage, name) + " is a pyopencl array that is not C-contiguous (copy() makes one)");
  if (array_.attr("offset").cast<size_t>() != 0)
    throw py::value_error(where(stage, name) + " is a pyopencl view at an offset into its buffer (copy() makes one)");
  if (clHandle(array_.attr("context"), "context") != reinterpret_cast<uintptr_t>(ctx.clContext()))
    throw py::value_error(where(stage, name) +
                          " is a pyopencl array of another cl_context than the penumbra.Context's "
                          "(penumbra.Context.from_queue makes one on the array's queue)");
  queue_ = array_.attr("queue");
  if (queue_.is_none())
    throw py::value_error(where(stage, name) + " is a pyopencl array without a queue (with_queue() gives it one)");
  for (const py::handle& dim : array_.attr("shape")) shape_.push_back(dim.cast<py::ssize_t>());
  const py::object data = array_.attr("base_data");
  deviceMem_ = data.is_none() ? nullptr : reinterpret_cast<cl_mem>(clHandle(data, "base_data"));
  for (const py::handle& event : array_.attr("events")) {
    const auto e = reinterpret_cast<cl_event>(clHandle(event, "event"));
    clRetainEvent(e);
    waits_.push_back(e);
  }
}

ArrayIn::~ArrayIn() {
  for (cl_event e : waits_) clReleaseEvent(e);
}

ArrayOut::ArrayOut(const Context& ctx, const ArrayIn& like, const std::vector<py::ssize_t>& dims, const char* dtype)
    : ctx_(ctx), device_(like.onDevice()), bytes_(byteCount(dims, dtype)) {
  const py::tuple shape = py::cast(dims);
  if (!device_) {
    array_ = py::array(py::dtype(dtype), dims);
    buffer_ = DeviceBuffer(ctx, bytes_);
    return;
  }
  array_ = py::module_::import("pyopencl.array").attr("empty")(like.queue(), shape, py::dtype(dtype));
  const py::object data = array_.attr("base_data");
  deviceMem_ = data.is_none() ? nullptr : reinterpret_cast<cl_mem>(clHandle(data, "base_data"));
}

py::object ArrayOut::finish(cl_event event) {
  if (device_) {
    array_.attr("add_event")(py::module_::import("pyopencl")
                                 .attr("Event")
                                 .attr("from_int_ptr")(reinterpret_cast<uintptr_t>(event), py::arg("retain") = true));
    return array_;
  }
  void* out = array_.cast<py::array>().mutable_data();
  clRetainEvent(event);  // download releases one reference
  {
    py::gil_scoped_release release;
    download(ctx_, buffer_.get(), event, out, bytes_);
  }
  return array_;
}

}  // namespace penumbra::python
