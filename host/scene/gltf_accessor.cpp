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
    case TINYGLTF_TYPE_MAT4:
      return "MAT4";
    default:
      return "another matrix or an invalid type";
  }
}

const char* typeOf(int components) {
  switch (components) {
    case 1:
      return "SCALAR";
    case 2:
      return "VEC2";
    case 3:
      return "VEC3";
    case 4:
      return "VEC4";
    default:
      return "MAT4";
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

// The accessor type's number of components (SCALAR 1 ... MAT4 16); 0 for anything else.
int componentCount(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      return 1;
    case TINYGLTF_TYPE_VEC2:
      return 2;
    case TINYGLTF_TYPE_VEC3:
      return 3;
    case TINYGLTF_TYPE_VEC4:
      return 4;
    case TINYGLTF_TYPE_MAT4:
      return 16;
    default:
      return 0;
  }
}

uint64_t componentSize(int componentType) {
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return 4;
    default:
      return 0;
  }
}

// One component at p as a float: FLOAT as is, normalized integers per glTF 2.0 sec. 3.11.
float decodeComponent(const unsigned char* p, int componentType) {
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: {
      float v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return static_cast<float>(*p) / 255.0f;
    case TINYGLTF_COMPONENT_TYPE_BYTE:
      return std::max(static_cast<float>(static_cast<int8_t>(*p)) / 127.0f, -1.0f);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t v;
      std::memcpy(&v, p, 2);
      return static_cast<float>(v) / 65535.0f;
    }
    default: {  // SHORT
      int16_t v;
      std::memcpy(&v, p, 2);
      return std::max(static_cast<float>(v) / 32767.0f, -1.0f);
    }
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

// Calls store(sparse index, its value's bytes) for every sparse value (each `elemSize` bytes).
template <class Store>
void applySparse(const GltfContext& ctx, int index, const tinygltf::Accessor& a, uint64_t elemSize, Store store) {
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
    store(target, val.data + i * elemSize);
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
    failGltf(ctx, fmt::format("accessor {}: {} must be VEC3 of FLOAT, got {} of {}{}", index, semantic,
                              typeName(a.type), a.normalized ? "normalized " : "", componentName(a.componentType)));
  const Strided src = locateAccessor(ctx, index, a, 12);
  std::vector<glm::vec3> out(a.count, glm::vec3(0.0f));
  if (src.data)
    for (size_t i = 0; i < a.count; ++i) std::memcpy(&out[i], src.data + i * src.stride, 12);
  applySparse(ctx, index, a, 12, [&out](uint32_t i, const unsigned char* p) { std::memcpy(&out[i], p, 12); });
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
  const std::vector<float> values = readFloats(ctx, index, 2, true, semantic.c_str());  // the checks above first
  std::vector<glm::vec2> out(values.size() / 2);
  for (size_t i = 0; i < out.size(); ++i) out[i] = glm::vec2(values[2 * i], values[2 * i + 1]);
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
  applySparse(ctx, index, a, size, [&out, size](uint32_t i, const unsigned char* p) { out[i] = readIndex(p, size); });
  return out;
}

std::vector<float> readFloats(const GltfContext& ctx, int index, int components, bool normalizedToo,
                              const char* semantic) {
  const tinygltf::Accessor& a = accessorAt(ctx, index);
  const bool normalized = a.normalized && a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT &&
                          a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT;
  const bool typeOk = a.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT ? !a.normalized : normalizedToo && normalized;
  if (componentCount(a.type) != components || !typeOk)
    failGltf(ctx, fmt::format("accessor {}: {} must be {} of FLOAT{}, got {} of {}{}", index, semantic,
                              typeOf(components), normalizedToo ? " or of a normalized integer type" : "",
                              typeName(a.type), a.normalized ? "normalized " : "", componentName(a.componentType)));
  // Matrices of 1- and 2-byte components pad their columns to 4 bytes (sec. 3.6.2.4); MAT4 of FLOAT has none.
  const uint64_t csize = componentSize(a.componentType), n = static_cast<uint64_t>(components);
  if (components == 16 && csize < 4)
    failGltf(ctx, fmt::format("accessor {}: {} must be MAT4 of FLOAT", index, semantic));
  const Strided src = locateAccessor(ctx, index, a, n * csize);
  std::vector<float> out(a.count * n, 0.0f);
  auto decode = [&](float* dst, const unsigned char* p) {
    for (uint64_t c = 0; c < n; ++c) dst[c] = decodeComponent(p + c * csize, a.componentType);
  };
  if (src.data)
    for (size_t i = 0; i < a.count; ++i) decode(&out[i * n], src.data + i * src.stride);
  applySparse(ctx, index, a, n * csize, [&](uint32_t i, const unsigned char* p) { decode(&out[i * n], p); });
  return out;
}

std::vector<glm::uvec4> readJoints(const GltfContext& ctx, int index, const char* semantic) {
  const tinygltf::Accessor& a = accessorAt(ctx, index);
  const uint64_t csize = a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE    ? 1
                         : a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ? 2
                                                                                     : 0;
  if (a.type != TINYGLTF_TYPE_VEC4 || csize == 0 || a.normalized)
    failGltf(ctx, fmt::format("accessor {}: {} must be VEC4 of UNSIGNED_BYTE or UNSIGNED_SHORT, got {} of {}", index,
                              semantic, typeName(a.type), componentName(a.componentType)));
  const Strided src = locateAccessor(ctx, index, a, 4 * csize);
  std::vector<glm::uvec4> out(a.count, glm::uvec4(0u));
  auto decode = [csize](glm::uvec4& v, const unsigned char* p) {
    for (int c = 0; c < 4; ++c) v[c] = readIndex(p + static_cast<uint64_t>(c) * csize, csize);
  };
  if (src.data)
    for (size_t i = 0; i < a.count; ++i) decode(out[i], src.data + i * src.stride);
  applySparse(ctx, index, a, 4 * csize, [&](uint32_t i, const unsigned char* p) { decode(out[i], p); });
  return out;
}

}  // namespace penumbra::detail
