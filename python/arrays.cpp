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

// pyopencl's module `name` when whoever calls us imported it (else nothing of theirs can be a pyopencl object).
py::object importedModule(const char* name) {
  const py::dict modules = py::module_::import("sys").attr("modules");
  return modules.contains(name) ? py::reinterpret_borrow<py::object>(modules[name]) : py::none();
}

bool isBuffer(const py::handle& object) {
  const py::object cl = importedModule("pyopencl");
  return !cl.is_none() && py::isinstance(object, cl.attr("Buffer"));
}

bool sameContext(const Context& ctx, const py::handle& object) {
  return clHandle(object.attr("context"), "context") == reinterpret_cast<uintptr_t>(ctx.clContext());
}

// A pyopencl array penumbra can read or write in place: of `dtype`, C-contiguous, not a view at an offset, on the
// context's cl_context and with a queue; else a ValueError that says how to get one.
void checkDeviceArray(const Context& ctx, const py::object& array, const char* dtype, const std::string& what) {
  if (!py::dtype(dtype).equal(array.attr("dtype")))
    throw py::value_error(what + " is a pyopencl array of " + py::str(array.attr("dtype")).cast<std::string>() +
                          ", not " + dtype + " (astype() makes one)");
  if (!array.attr("flags").attr("c_contiguous").cast<bool>())
    throw py::value_error(what + " is a pyopencl array that is not C-contiguous (copy() makes one)");
  if (array.attr("offset").cast<size_t>() != 0)
    throw py::value_error(what + " is a pyopencl view at an offset into its buffer (copy() makes one)");
  if (!sameContext(ctx, array))
    throw py::value_error(what +
                          " is a pyopencl array of another cl_context than the penumbra.Context's "
                          "(penumbra.Context.from_queue makes one on the array's queue)");
  if (array.attr("queue").is_none())
    throw py::value_error(what + " is a pyopencl array without a queue (with_queue() gives it one)");
}

cl_mem baseMem(const py::object& array) {
  const py::object data = array.attr("base_data");
  return data.is_none() ? nullptr : reinterpret_cast<cl_mem>(clHandle(data, "base_data"));
}

// The array's pending events, retained (the caller releases them).
std::vector<cl_event> retainedEvents(const py::object& array) {
  std::vector<cl_event> events;
  for (const py::handle& event : array.attr("events")) {
    const auto e = reinterpret_cast<cl_event>(clHandle(event, "event"));
    clRetainEvent(e);
    events.push_back(e);
  }
  return events;
}

}  // namespace

bool isDeviceArray(const py::handle& object) {
  const py::object array = importedModule("pyopencl.array");
  return !array.is_none() && py::isinstance(object, array.attr("Array"));
}

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
  checkDeviceArray(ctx, array_, dtype, where(stage, name));
  queue_ = array_.attr("queue");
  for (const py::handle& dim : array_.attr("shape")) shape_.push_back(dim.cast<py::ssize_t>());
  deviceMem_ = baseMem(array_);
  waits_ = retainedEvents(array_);
}

ArrayIn::~ArrayIn() {
  for (cl_event e : waits_) clReleaseEvent(e);
}

ArrayOut::ArrayOut(const Context& ctx, const ArrayIn& like, const std::vector<py::ssize_t>& dims, const char* dtype,
                   const py::handle& into, const char* stage)
    : ctx_(ctx), device_(like.onDevice() || !into.is_none()), bytes_(byteCount(dims, dtype)) {
  const py::tuple shape = py::cast(dims);
  if (!device_) {
    array_ = py::array(py::dtype(dtype), dims);
    buffer_ = DeviceBuffer(ctx, bytes_);
    return;
  }
  const std::string what = where(stage, "out");
  if (into.is_none()) {
    array_ = py::module_::import("pyopencl.array").attr("empty")(like.queue(), shape, py::dtype(dtype));
  } else if (isDeviceArray(into)) {
    array_ = py::reinterpret_borrow<py::object>(into);
    checkDeviceArray(ctx, array_, dtype, what);
    const py::object actual = array_.attr("shape");
    if (!actual.equal(shape))
      throw py::value_error(what + " has the shape " + py::repr(actual).cast<std::string>() + ", not " +
                            py::repr(shape).cast<std::string>());
    waits_ = retainedEvents(array_);
  } else if (isBuffer(into)) {
    if (!like.onDevice())
      throw py::value_error(what +
                            " is a pyopencl Buffer, which needs a pyopencl array as the input (its queue carries the "
                            "result); pass out= a pyopencl array instead");
    if (!sameContext(ctx, into))
      throw py::value_error(what + " is a pyopencl Buffer of another cl_context than the penumbra.Context's");
    const size_t size = into.attr("size").cast<size_t>();
    if (size < bytes_)
      throw py::value_error(what + " is a pyopencl Buffer of " + std::to_string(size) + " bytes; the result takes " +
                            std::to_string(bytes_));
    array_ = py::module_::import("pyopencl.array")
                 .attr("Array")(like.queue(), shape, py::dtype(dtype), py::arg("data") = into);
  } else {
    throw py::type_error(what + ": a pyopencl array or Buffer, not " + py::str(py::type::of(into)).cast<std::string>());
  }
  deviceMem_ = baseMem(array_);
}

ArrayOut::~ArrayOut() {
  for (cl_event e : waits_) clReleaseEvent(e);
}

std::vector<cl_event> ArrayOut::waits(const ArrayIn& in) const {
  std::vector<cl_event> all = in.waits();
  all.insert(all.end(), waits_.begin(), waits_.end());
  return all;
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
