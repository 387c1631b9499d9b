// Image alpha for alpha-tested materials: stb_image's implementation lives in this translation unit only
// (STB_IMAGE_STATIC: no clash with another stb in the program). The header is read first (stbi_info), so an image
// without alpha is never decoded and the texture budget is claimed before any pixel memory is taken.
#include "host/scene/gltf_images.h"

#include <fmt/format.h>

#include <algorithm>
#include <limits>
#include <memory>
#include <span>

#include "host/scene/gltf_tinygltf.h"

#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#include <stb_image.h>

namespace penumbra::detail {
namespace {

[[noreturn]] void failImage(const GltfContext& ctx, int image, const std::string& message) {
  failGltf(ctx, fmt::format("{}: {}", imageLabel(ctx, image), message));
}

// The encoded bytes of a buffer-view image, checked against its buffer.
std::span<const unsigned char> viewBytes(const GltfContext& ctx, int image, int viewIndex) {
  const tinygltf::BufferView& view = ctx.model.bufferViews.at(static_cast<size_t>(viewIndex));
  if (view.buffer < 0 || static_cast<size_t>(view.buffer) >= ctx.model.buffers.size())
    failImage(ctx, image, fmt::format("bufferView {}: buffer {} does not exist", viewIndex, view.buffer));
  const std::vector<unsigned char>& data = ctx.model.buffers[static_cast<size_t>(view.buffer)].data;
  if (view.byteOffset > data.size() || view.byteLength > data.size() - view.byteOffset)
    failImage(ctx, image,
              fmt::format("bufferView {}: bytes {}..{} run past the end of buffer {} ({} bytes)", viewIndex,
                          view.byteOffset, uint64_t{view.byteOffset} + view.byteLength, view.buffer, data.size()));
  return {data.data() + view.byteOffset, view.byteLength};
}

// The encoded bytes of an image from wherever the file keeps them; `file` holds an external file's bytes.
std::span<const unsigned char> encodedBytes(const GltfContext& ctx, const ImageSources& sources, int image,
                                            std::vector<unsigned char>& file) {
  const tinygltf::Image& img = ctx.model.images[static_cast<size_t>(image)];
  if (img.bufferView >= 0) return viewBytes(ctx, image, img.bufferView);
  if (const auto it = sources.dataUri.find(image); it != sources.dataUri.end()) return it->second;
  if (img.uri.rfind("data:", 0) == 0)
    failImage(ctx, image, "data: URI of an unsupported media type (image/png, image/jpeg, image/bmp, image/gif)");
  try {
    file = sources.reader.read(resolveInside(sources.root, decodeUri(img.uri)));
  } catch (const SceneError& e) {
    failImage(ctx, image, e.what());
  }
  return file;
}

// The container the bytes start with (the formats stb_image decodes that glTF allows or tolerates), "" for none.
std::string_view imageFormat(std::span<const unsigned char> b) {
  const auto starts = [&](std::initializer_list<unsigned char> magic) {
    return b.size() >= magic.size() && std::equal(magic.begin(), magic.end(), b.begin());
  };
  if (starts({0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'})) return "PNG";
  if (starts({0xff, 0xd8, 0xff})) return "JPEG";
  if (starts({'B', 'M'})) return "BMP";
  if (starts({'G', 'I', 'F', '8'})) return "GIF";
  return "";
}

// Why stb_image refused the bytes, in words that name the problem: no known container (its first bytes), a PNG whose
// header declares more than stb_image's 2^24 pixels a side, or a known container stb_image could not read (its reason;
// a truncated file often gives none).
std::string undecodable(std::span<const unsigned char> b) {
  const std::string_view format = imageFormat(b);
  if (format.empty()) {
    std::string first;
    for (size_t i = 0; i < std::min<size_t>(b.size(), 8); ++i) first += fmt::format("{}{:02x}", i ? " " : "", b[i]);
    return fmt::format("not a PNG, JPEG, BMP or GIF image (its first bytes: {})", first);
  }
  if (format == "PNG" && b.size() >= 24 && std::equal(b.begin() + 12, b.begin() + 16, "IHDR")) {
    const auto be32 = [&](size_t at) {
      return uint32_t{b[at]} << 24 | uint32_t{b[at + 1]} << 16 | uint32_t{b[at + 2]} << 8 | uint32_t{b[at + 3]};
    };
    const uint32_t width = be32(16), height = be32(20);
    if (width > (1u << 24) || height > (1u << 24))
      return fmt::format("a PNG of {}x{} pixels: more than the decoder's {} pixels a side", width, height, 1u << 24);
  }
  const char* reason = stbi_failure_reason();
  return fmt::format(
      "a {} of {} bytes that cannot be decoded ({})", format, b.size(),
      reason && *reason && std::string_view(reason) != "unknown image type" ? reason : "truncated or corrupt");
}

}  // namespace

std::string imageLabel(const GltfContext& ctx, int image) {
  const tinygltf::Image& img = ctx.model.images.at(static_cast<size_t>(image));
  const std::string name = !img.name.empty() ? img.name : img.uri.rfind("data:", 0) == 0 ? std::string() : img.uri;
  return name.empty() ? fmt::format("image {}", image) : fmt::format("image {} \"{}\"", image, visible(name));
}

DecodedAlpha decodeImageAlpha(const GltfContext& ctx, const ImageSources& sources, int image) {
  std::vector<unsigned char> file;
  const std::span<const unsigned char> bytes = encodedBytes(ctx, sources, image, file);
  if (bytes.empty() || bytes.size() > static_cast<size_t>(std::numeric_limits<int>::max()))
    failImage(ctx, image, fmt::format("{} bytes of image data", bytes.size()));
  const int size = static_cast<int>(bytes.size());
  // Sec. 5.18: mimeType names the image's format; the bytes are decoded as what they are, and a mismatch is said.
  const tinygltf::Image& img = ctx.model.images[static_cast<size_t>(image)];
  const std::string_view format = imageFormat(bytes);
  const bool declaredPng = img.mimeType == "image/png", declaredJpeg = img.mimeType == "image/jpeg";
  if ((declaredPng && format != "PNG") || (declaredJpeg && format != "JPEG"))
    emitWarning(ctx.options, fmt::format("{}: {}: declared {} but its bytes are {}", ctx.file, imageLabel(ctx, image),
                                         img.mimeType, format.empty() ? "no PNG or JPEG" : format));
  int width = 0, height = 0, channels = 0;
  if (!stbi_info_from_memory(bytes.data(), size, &width, &height, &channels)) failImage(ctx, image, undecodable(bytes));
  DecodedAlpha out;
  out.width = static_cast<uint32_t>(width), out.height = static_cast<uint32_t>(height);
  out.hasAlpha = channels == 2 || channels == 4;  // grey + alpha, RGBA
  if (!out.hasAlpha) return out;
  const uint64_t texels = uint64_t{out.width} * out.height;
  if (texels * static_cast<uint64_t>(channels) > sources.reader.maxTextureBytes())
    failImage(ctx, image,
              fmt::format("{}x{} with {} channels decodes to more than the limit of {} bytes of textures", width,
                          height, channels, sources.reader.maxTextureBytes()));
  try {
    sources.reader.claimTextureBytes(texels, fmt::format("{}x{}", width, height));
  } catch (const SceneError& e) {
    failImage(ctx, image, e.what());
  }
  const std::unique_ptr<stbi_uc, void (*)(void*)> pixels(
      stbi_load_from_memory(bytes.data(), size, &width, &height, &channels, 0), &stbi_image_free);
  if (!pixels) failImage(ctx, image, undecodable(bytes));
  if (static_cast<uint32_t>(width) != out.width || static_cast<uint32_t>(height) != out.height ||
      !(channels == 2 || channels == 4))
    failImage(ctx, image, "its header and its pixels disagree");
  out.texels.resize(texels);
  for (uint64_t i = 0; i < texels; ++i) out.texels[i] = pixels.get()[i * static_cast<uint64_t>(channels) + channels - 1];
  return out;
}

}  // namespace penumbra::detail
