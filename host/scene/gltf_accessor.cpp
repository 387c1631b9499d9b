// Accessor reading (glTF 2.0 spec 3.6 "Binary Data Storage", 3.6.2.3 "Sparse Accessors"). Every byte
// range is checked in 64-bit arithmetic with overflow checks before a single byte is read; reads use
// memcpy, so misaligned data is safe.
#include "host/scene/gltf_accessor.h"

#include <cstring>

#include <fmt/format.h>

#include "host/scene/load_options.h"

namespace penumbra::detail {
namespace {

// An accessor without bufferView is all zeros (a base for sparse values): its size is not bounded by any
// buffer, so it gets a cap of its own, far above real use (sparse morph targets, zero-initialised data).
constexpr uint64_t kMaxZeroAccessorElements = uint64_t{1} << 24;

struct Strided {
  const unsigned char* data = nullptr;  // nullptr: an accessor without bufferView (all zeros)
  uint64_t stride = 0;
};

const char* componentName(int type) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
      return "BYTE";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return "UNSIGNED_BYTE";
    case TINYGLTF_COMPONENT_TYPE_SHORT:
      return "SHORT";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return "UNSIGNED_SHORT";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
      return "UNSIGNED_INT";
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return "FLOAT";
    default:
      return "an invalid component type";
  }
}

const char* typeName(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      return "SCALAR";
    case TINYGLTF_TYPE_VEC2:
      return "VEC2";
    case TINYGLTF_TYPE_VEC3:
      return "VEC3";
    case TINYGLTF_TYPE_VEC4:
      return "VEC4";
    default:
      return "a matrix or invalid type";
  }
}

uint64_t indexSize(int componentType) {
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return 1;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
      return 4;
    default:
      return 0;
  }
}

uint32_t readIndex(const unsigned char* p, uint64_t size) {
  if (size == 1) return *p;
  if (size == 2) {
    uint16_t v;
    std::memcpy(&v, p, 2);
    return v;
  }
  uint32_t v;
  std::memcpy(&v, p, 4);
  return v;
}

// `count` elements of `elemSize` bytes, `stride` apart, from `offset` in bufferView `viewIndex`.
Strided locate(const GltfContext& ctx, const std::string& what, int viewIndex, uint64_t offset, uint64_t count,
               uint64_t elemSize, uint64_t stride) {
  const auto& views = ctx.model.bufferViews;
  if (viewIndex < 0 || static_cast<size_t>(viewIndex) >= views.size())
    failGltf(ctx, fmt::format("{}: bufferView {} does not exist", what, viewIndex));
  const tinygltf::BufferView& view = views[static_cast<size_t>(viewIndex)];
  if (view.buffer < 0 || static_cast<size_t>(view.buffer) >= ctx.model.buffers.size())
    failGltf(ctx, fmt::format("bufferView {}: buffer {} does not exist", viewIndex, view.buffer));
  const uint64_t bufferSize = ctx.model.buffers[static_cast<size_t>(view.buffer)].data.size();
  if (view.byteOffset > bufferSize || view.byteLength > bufferSize - view.byteOffset)
    failGltf(ctx, fmt::format("bufferView {}: bytes {}..{} run past the end of buffer {} ({} bytes)", viewIndex,
                              view.byteOffset, uint64_t{view.byteOffset} + view.byteLength, view.buffer, bufferSize));
  uint64_t span = 0, end = 0;
  if (__builtin_mul_overflow(stride, count - 1, &span) || __builtin_add_overflow(span, elemSize, &span) ||
      __builtin_add_overflow(span, offset, &end))
    failGltf(ctx, fmt::format("{}: count {} x stride {} overflows", what, count, stride));
  if (end > view.byteLength)
    failGltf(ctx,
             fmt::format("{}: {} elements of {} bytes (stride {}) from byte {} need {} bytes, bufferView {} has {}",
                         what, count, elemSize, stride, offset, end, viewIndex, view.byteLength));
  return {ctx.model.buffers[static_cast<size_t>(view.buffer)].data.data() + view.byteOffset + offset, stride};
}

Strided locateAccessor(const GltfContext& ctx, int index, const tinygltf::Accessor& a, uint64_t elemSize) {
  const std::string what = fmt::format("accessor {}", index);
  if (a.count == 0 || a.count > ctx.maxElements())
    failGltf(ctx, fmt::format("{}: count {} is outside 1..{}", what, a.count, ctx.maxElements()));
  if (a.bufferView < 0) {
    if (a.count > kMaxZeroAccessorElements)
      failGltf(ctx,
               fmt::format("{}: count {} without a bufferView exceeds {}", what, a.count, kMaxZeroAccessorElements));
    return {};
  }
  const auto& views = ctx.model.bufferViews;
  const uint64_t viewStride =
      static_cast<size_t>(a.bufferView) < views.size() ? views[static_cast<size_t>(a.bufferView)].byteStride : 0;
  if (viewStride != 0 && viewStride < elemSize)
    failGltf(ctx, fmt::format("{}: byteStride {} is smaller than an element ({} bytes)", what, viewStride, elemSize));
  return locate(ctx, what, a.bufferView, a.byteOffset, a.count, elemSize, viewStride ? viewStride : elemSize);
}

// Overwrites out[sparse index] with the sparse values (each `elemSize` bytes, copied by `store`).
template <class T, class Store>
void applySparse(const GltfContext& ctx, int index, const tinygltf::Accessor& a, uint64_t elemSize, std::vector<T>& out,
                 Store store) {
  if (!a.sparse.isSparse) return;
  const std::string what = fmt::format("accessor {}: sparse", index);
  const auto& s = a.sparse;
  const uint64_t isize = indexSize(s.indices.componentType);
  if (s.count < 1 || static_cast<uint64_t>(s.count) > a.count)
    failGltf(ctx, fmt::format("{}: count {} is outside 1..{}", what, s.count, a.count));
  if (isize == 0 || s.indices.byteOffset < 0 || s.values.byteOffset < 0)
    failGltf(ctx, fmt::format("{}: bad indices component type or negative byte offset", what));
  const auto n = static_cast<uint64_t>(s.count);
  const Strided idx = locate(ctx, what + " indices", s.indices.bufferView, static_cast<uint64_t>(s.indices.byteOffset),
                             n, isize, isize);
  const Strided val = locate(ctx, what + " values", s.values.bufferView, static_cast<uint64_t>(s.values.byteOffset), n,
                             elemSize, elemSize);
  for (uint64_t i = 0, previous = 0; i < n; ++i) {
    const uint32_t target = readIndex(idx.data + i * isize, isize);
    if (target >= a.count || (i > 0 && target <= previous))
      failGltf(ctx, fmt::format("{}: index {} at position {} is out of range or not increasing", what, target, i));
    store(out[target], val.data + i * elemSize);
    previous = target;
  }
}

}  // namespace

void failGltf(const GltfContext& ctx, const std::string& message) {
  throw SceneError(fmt::format("{}: {}", ctx.file, message));
}

const tinygltf::Accessor& accessorAt(const GltfContext& ctx, int index) {
  if (index < 0 || static_cast<size_t>(index) >= ctx.model.accessors.size())
    failGltf(ctx, fmt::format("accessor {} does not exist", index));
  return ctx.model.accessors[static_cast<size_t>(index)];
}

std::vector<glm::vec3> readVec3(const GltfContext& ctx, int index, const char* semantic) {
  const tinygltf::Accessor& a = accessorAt(ctx, index);
  if (a.type != TINYGLTF_TYPE_VEC3 || a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT || a.normalized)
    failGltf(ctx, fmt::format("accessor {}: {} must be VEC3 of FLOAT, got {} of {}", index, semantic, typeName(a.type),
                              componentName(a.componentType)));
  const Strided src = locateAccessor(ctx, index, a, 12);
  std::vector<glm::vec3> out(a.count, glm::vec3(0.0f));
  if (src.data)
    for (size_t i = 0; i < a.count; ++i) std::memcpy(&out[i], src.data + i * src.stride, 12);
  applySparse(ctx, index, a, 12, out, [](glm::vec3& v, const unsigned char* p) { std::memcpy(&v, p, 12); });
  return out;
}

std::vector<glm::vec2> readVec2(const GltfContext& ctx, int index, const std::string& semantic) {
  const tinygltf::Accessor& a = accessorAt(ctx, index);
  const int type = a.componentType;
  const bool normalized =
      a.normalized && (type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE || type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
  if (a.type != TINYGLTF_TYPE_VEC2 || !(normalized || (type == TINYGLTF_COMPONENT_TYPE_FLOAT && !a.normalized)))
    failGltf(ctx,
             fmt::format("accessor {}: {} must be VEC2 of FLOAT or of normalized UNSIGNED_BYTE or UNSIGNED_SHORT, "
                         "got {} of {}{}",
                         index, semantic, typeName(a.type), a.normalized ? "normalized " : "", componentName(type)));
  const uint64_t size = type == TINYGLTF_COMPONENT_TYPE_FLOAT ? 4 : indexSize(type);
  // Normalized unsigned integers are c / (2^bits - 1), as glTF defines them.
  const auto load = [type, size](glm::vec2& v, const unsigned char* p) {
    if (type == TINYGLTF_COMPONENT_TYPE_FLOAT) {
      std::memcpy(&v, p, 8);
      return;
    }
    const float scale = type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ? 255.0f : 65535.0f;
    v = glm::vec2(static_cast<float>(readIndex(p, size)) / scale,
                  static_cast<float>(readIndex(p + size, size)) / scale);
  };
  const Strided src = locateAccessor(ctx, index, a, 2 * size);
  std::vector<glm::vec2> out(a.count, glm::vec2(0.0f));
  if (src.data)
    for (size_t i = 0; i < a.count; ++i) load(out[i], src.data + i * src.stride);
  applySparse(ctx, index, a, 2 * size, out, load);
  return out;
}

std::vector<uint32_t> readIndices(const GltfContext& ctx, int index) {
  const tinygltf::Accessor& a = accessorAt(ctx, index);
  const uint64_t size = indexSize(a.componentType);
  if (a.type != TINYGLTF_TYPE_SCALAR || size == 0 || a.normalized)
    failGltf(ctx, fmt::format("accessor {}: indices must be SCALAR of UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT, "
                              "got {} of {}",
                              index, typeName(a.type), componentName(a.componentType)));
  if (a.bufferView >= 0 && static_cast<size_t>(a.bufferView) < ctx.model.bufferViews.size() &&
      ctx.model.bufferViews[static_cast<size_t>(a.bufferView)].byteStride != 0)
    failGltf(ctx, fmt::format("accessor {}: index data must be tightly packed (bufferView {} has a byteStride)", index,
                              a.bufferView));
  const Strided src = locateAccessor(ctx, index, a, size);
  std::vector<uint32_t> out(a.count, 0u);
  if (src.data)
    for (size_t i = 0; i < a.count; ++i) out[i] = readIndex(src.data + i * size, size);
  applySparse(ctx, index, a, size, out, [size](uint32_t& v, const unsigned char* p) { v = readIndex(p, size); });
  return out;
}

}  // namespace penumbra::detail
