// Copies into part of a buffer, with Oclgrind's workaround beside it.
#include "host/cl/buffer_copy.h"

#include <stdexcept>

#include "host/cl/kernel.h"

namespace penumbra {

template <class T>
void copyInto(Context& ctx, const Buffer<T>& src, Buffer<T>& dst, size_t offset, size_t count) {
  if (offset + count > dst.size() || count > src.size()) throw std::out_of_range("copyInto past the end");
  if (ctx.info().isSimulator()) {
    // Oclgrind 21.10's uninitialised-value check takes a copy's (or write's) n bytes at an offset o > 0 for the
    // whole destination: its shadow memory becomes n bytes long and the copy is dropped from it, so every split but
    // the first read as uninitialised (tests/data/oclgrind/offset_store.c). A kernel's stores are tracked one by one.
    static_assert(sizeof(T) == 4 || sizeof(T) == 2, "copy_into_u32 or copy_into_u16");
    Kernel copy(ctx, "kernels/fill.cl", sizeof(T) == 4 ? "copy_into_u32" : "copy_into_u16", "transfer");
    copy.args(src, dst, static_cast<cl_uint>(offset), static_cast<cl_uint>(count))
        .moves(2 * count * sizeof(T))
        .launch(count, 64);
    return;
  }
  cl::Event event;
  clCheck(ctx.queue().enqueueCopyBuffer(src.get(), dst.get(), 0, offset * sizeof(T), count * sizeof(T), nullptr,
                                        &event),
          "clEnqueueCopyBuffer", {}, "transfer");
  if (ctx.profiler() != nullptr) ctx.profiler()->record("transfer/copy", event, 2 * count * sizeof(T));
}
template void copyInto(Context&, const Buffer<float>&, Buffer<float>&, size_t, size_t);
template void copyInto(Context&, const Buffer<cl_half>&, Buffer<cl_half>&, size_t, size_t);
template void copyInto(Context&, const Buffer<uint32_t>&, Buffer<uint32_t>&, size_t, size_t);

}  // namespace penumbra
