// Copies `count` elements of one buffer into another at an element offset (one "transfer/copy" pass): the split
// techniques gather their maps into atlases this way. On Oclgrind the copy runs as a kernel (see buffer_copy.cpp).
#pragma once

#include <cstddef>

#include "host/cl/buffer.h"
#include "host/cl/context.h"

namespace penumbra {

// Copies `count` elements of `src` into `dst` at element `offset`; float, cl_half or uint32_t (triangle ids).
// Throws std::out_of_range past either end.
template <class T>
void copyInto(Context& ctx, const Buffer<T>& src, Buffer<T>& dst, size_t offset, size_t count);

}  // namespace penumbra
