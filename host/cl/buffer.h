// A typed device buffer: element count, upload/download, fill (used to poison outputs in tests).
// OpenCL forbids zero-sized buffers, so an empty Buffer still owns one element.
#pragma once

#include <CL/opencl.hpp>
#include <algorithm>
#include <numeric>
#include <span>
#include <string>
#include <vector>

#include "host/cl/context.h"
#include "host/cl/error.h"
#include "host/cl/profiler.h"

namespace penumbra {

template <class T>
class Buffer {
 public:
  Buffer() = default;
  Buffer(Context& ctx, size_t count, cl_mem_flags flags = CL_MEM_READ_WRITE) { allocate(ctx, count, flags); }
  Buffer(Context& ctx, std::span<const T> data, cl_mem_flags flags = CL_MEM_READ_WRITE) {
    allocate(ctx, data.size(), flags);
    upload(ctx, data);
  }

  // A read-only buffer created holding a copy of `data` (CL_MEM_COPY_HOST_PTR): no command on the queue, so unlike
  // the uploading constructor it never waits for what the queue holds (a caller's events, issue 17's interop).
  static Buffer copyOf(Context& ctx, std::span<const T> data) {
    Buffer copy;
    cl_int err = CL_SUCCESS;
    copy.flags_ = CL_MEM_READ_ONLY;
    copy.buffer_ = cl::Buffer(ctx.context(), CL_MEM_READ_ONLY | (data.empty() ? 0 : CL_MEM_COPY_HOST_PTR),
                              std::max<size_t>(data.size(), 1) * sizeof(T), const_cast<T*>(data.data()), &err);
    clCheck(err, "clCreateBuffer(CL_MEM_COPY_HOST_PTR)");
    if (ctx.info().isSimulator()) ctx.retire(copy.buffer_);  // Context::retire
    copy.count_ = data.size();
    copy.context_ = ctx.context()();
    return copy;
  }

  // `count` elements over memory someone else created (the public API's caller's cl_mem, in `context`): `memory`
  // holds a retain of its own, released with this Buffer, so the owner's reference count ends where it began.
  static Buffer over(cl::Buffer memory, size_t count, cl_context context) {
    Buffer view;
    view.buffer_ = std::move(memory);
    view.count_ = count;
    view.context_ = context;
    return view;
  }

  // Makes this hold `count` elements of undefined contents. Keeps the current device memory when it already
  // has that count and flags in that context: a stage that re-allocates its buffers every frame then reuses
  // them (fresh allocations cost page faults on first touch, ~200 MB/s on PoCL, and driver allocations on GPUs).
  void allocate(Context& ctx, size_t count, cl_mem_flags flags = CL_MEM_READ_WRITE) {
    if (buffer_() != nullptr && count == count_ && flags == flags_ && context_ == ctx.context()()) return;
    if (count > ctx.info().maxAllocBytes / sizeof(T))
      throwBufferTooLarge(count, sizeof(T), ctx.info().maxAllocBytes);
    cl_int err = CL_SUCCESS;
    buffer_ = cl::Buffer(ctx.context(), flags, std::max<size_t>(count, 1) * sizeof(T), nullptr, &err);
    clCheck(err, "clCreateBuffer");
    if (ctx.info().isSimulator()) ctx.retire(buffer_);  // Context::retire: held until the context goes
    count_ = count;
    flags_ = flags;
    context_ = ctx.context()();
  }

  // Elements [first, first + count) as a Buffer of their own sharing this one's memory (clCreateSubBuffer), so
  // that a stage can write straight into a slice of a larger array. first * sizeof(T) must be a multiple of
  // ctx.info().baseAddressAlignBytes (alignedCount() rounds a slice's stride up to one). Commands on one in-order
  // queue may use the region and its parent one after the other.
  Buffer region(Context& ctx, size_t first, size_t count) const {
    if (first + count > count_) throw std::out_of_range("Buffer::region past the end");
    if (first * sizeof(T) % ctx.info().baseAddressAlignBytes != 0)
      throwMisalignedRegion(first * sizeof(T), ctx.info().baseAddressAlignBytes);
    const cl_buffer_region bytes{first * sizeof(T), std::max<size_t>(count, 1) * sizeof(T)};
    cl_int err = CL_SUCCESS;
    Buffer view;
    view.buffer_ = cl::Buffer(clCreateSubBuffer(buffer_.get(), 0, CL_BUFFER_CREATE_TYPE_REGION, &bytes, &err));
    clCheck(err, "clCreateSubBuffer");
    view.count_ = count;
    return view;
  }

  // `count` rounded up so that consecutive slices of that many elements each start at an aligned offset.
  static size_t alignedCount(Context& ctx, size_t count) {
    const size_t align = ctx.info().baseAddressAlignBytes, step = align / std::gcd(align, sizeof(T));
    return (count + step - 1) / step * step;
  }

  size_t size() const { return count_; }
  size_t bytes() const { return count_ * sizeof(T); }
  bool empty() const { return count_ == 0; }
  const cl::Buffer& get() const { return buffer_; }

  void upload(Context& ctx, std::span<const T> data, size_t offset = 0) {
    if (data.empty()) return;
    if (offset + data.size() > count_) throw std::out_of_range("Buffer::upload past the end");
    record(ctx, "upload", data.size_bytes(), [&](cl::Event* event) {
      return ctx.queue().enqueueWriteBuffer(buffer_, CL_TRUE, offset * sizeof(T), data.size_bytes(), data.data(),
                                            nullptr, event);
    });
  }

  std::vector<T> download(Context& ctx) const { return download(ctx, 0, count_); }

  // `count` elements from `offset`.
  std::vector<T> download(Context& ctx, size_t offset, size_t count) const {
    if (offset > count_ || count > count_ - offset) throw std::out_of_range("Buffer::download past the end");
    std::vector<T> data(count);
    if (count == 0) return data;
    const size_t size = count * sizeof(T);
    record(ctx, "download", size, [&](cl::Event* event) {
      return ctx.queue().enqueueReadBuffer(buffer_, CL_TRUE, offset * sizeof(T), size, data.data(), nullptr, event);
    });
    return data;
  }

  // Copies `source`'s elements to the start of this buffer on the device, without waiting ("transfer/copy").
  void copyFrom(Context& ctx, const Buffer& source) {
    if (source.count_ == 0) return;
    if (source.count_ > count_) throw std::out_of_range("Buffer::copyFrom past the end");
    record(ctx, "copy", 2 * source.bytes(), [&](cl::Event* event) {
      return ctx.queue().enqueueCopyBuffer(source.buffer_, buffer_, 0, 0, source.bytes(), nullptr, event);
    });
  }

  void fill(Context& ctx, const T& value) {
    if (count_ == 0) return;
    if (ctx.info().isSimulator()) {
      // Oclgrind 21.10's uninitialised-value check does not mark what clEnqueueFillBuffer writes as initialised, and
      // reports every later use of it (counters, poisoned outputs): there, the same bytes go through a write.
      const std::vector<T> values(count_, value);
      record(ctx, "fill", bytes(), [&](cl::Event* event) {
        return ctx.queue().enqueueWriteBuffer(buffer_, CL_TRUE, 0, bytes(), values.data(), nullptr, event);
      });
      return;
    }
    record(ctx, "fill", bytes(),
           [&](cl::Event* event) { return ctx.queue().enqueueFillBuffer(buffer_, value, 0, bytes(), nullptr, event); });
  }

 private:
  template <class Call>
  // `moved`: the bytes written (fill, upload) or read (download), for the bandwidth floor.
  static void record(Context& ctx, const char* what, uint64_t moved, Call&& call) {
    cl::Event event;
    clCheck(call(&event), std::string("Buffer::") + what, {}, "transfer");
    if (ctx.profiler() != nullptr) ctx.profiler()->record(std::string("transfer/") + what, event, moved);
  }

  cl::Buffer buffer_;
  size_t count_ = 0;
  cl_mem_flags flags_ = 0;
  cl_context context_ = nullptr;  // identity only (not retained): allocate()'s reuse check
};

}  // namespace penumbra
