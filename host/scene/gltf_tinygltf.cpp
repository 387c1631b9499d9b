// tinygltf's implementation lives in this translation unit only (TINYGLTF_IMPLEMENTATION), built without
// stb_image and without external images: tinygltf decodes no pixels (gltf_images.cpp decodes the images alpha masks
// need, with their URIs kept inside the scene's folder). Also holds the file-system callbacks that keep buffer URIs
// inside the scene's folder.
#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include "host/scene/gltf_tinygltf.h"

#include <fmt/format.h>

#include <algorithm>
#include <sstream>

namespace penumbra::detail {
namespace {

namespace fs = std::filesystem;

struct FsContext {
  fs::path root;
  std::string prefix;  // root + "/": tinygltf joins it with the URI
  FileReader* reader;
  std::string error;  // why the last read was refused
};

bool fileExists(const std::string& path, void* user) {
  // Only candidates under our root "exist"; tinygltf's fallback to the working directory never does.
  return path.rfind(static_cast<FsContext*>(user)->prefix, 0) == 0;
}

std::string expandFilePath(const std::string& path, void*) { return path; }  // no ~ or $VAR expansion

bool readWholeFile(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
  auto* ctx = static_cast<FsContext*>(user);
  try {
    if (path.rfind(ctx->prefix, 0) != 0) throw SceneError(fmt::format("\"{}\": outside the scene's folder", path));
    *out = ctx->reader->read(resolveInside(ctx->root, std::string_view(path).substr(ctx->prefix.size())));
    return true;
  } catch (const SceneError& e) {
    ctx->error = e.what();
    if (err) *err = e.what();
    return false;
  }
}

bool writeWholeFile(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
  if (err) *err = "writing is disabled";
  return false;
}

// Images are not decoded here; a data: URI's bytes are kept (tinygltf keeps no URI for it), others are left where they
// are (a buffer view, a file).
bool keepDataUriImage(tinygltf::Image* image, const int index, std::string*, std::string*, int, int,
                      const unsigned char* bytes, int size, void* user) {
  if (image->bufferView < 0 && size > 0)
    (*static_cast<std::map<int, std::vector<unsigned char>>*>(user))[index].assign(bytes, bytes + size);
  return true;
}

std::string firstLine(const std::string& text) {
  std::string line = text.substr(0, text.find('\n'));
  return line.empty() ? "tinygltf reported an error without a message" : line;
}

void forwardWarnings(const std::string& warn, const std::string& file, const LoadOptions& options) {
  std::istringstream lines(warn);
  for (std::string line; std::getline(lines, line);)
    if (!line.empty()) emitWarning(options, fmt::format("{}: {}", file, line));
}

}  // namespace

ParsedGltf parseWithTinygltf(const std::vector<unsigned char>& bytes, size_t byteCount, bool binary,
                             const fs::path& root, FileReader& reader, const std::string& file,
                             const LoadOptions& options) {
  FsContext ctx{root, root.string(), &reader, {}};
  if (ctx.prefix.empty() || ctx.prefix.back() != '/') ctx.prefix += '/';
  tinygltf::TinyGLTF loader;
  loader.SetFsCallbacks({&fileExists, &expandFilePath, &readWholeFile, &writeWholeFile, &ctx});
  ParsedGltf parsed;
  loader.SetImageLoader(&keepDataUriImage, &parsed.dataUriImages);
  tinygltf::Model& model = parsed.model;
  std::string err, warn;
  bool ok = false;
  try {
    const auto size = static_cast<unsigned int>(std::min(byteCount, bytes.size()));  // capped far below 4 GiB
    ok = binary ? loader.LoadBinaryFromMemory(&model, &err, &warn, bytes.data(), size, root.string())
                : loader.LoadASCIIFromString(&model, &err, &warn, reinterpret_cast<const char*>(bytes.data()), size,
                                             root.string());
  } catch (const std::exception& e) {
    throw SceneError(fmt::format("{}: {}", file, e.what()));
  }
  if (!ok) {
    if (!ctx.error.empty()) throw SceneError(fmt::format("{}: buffer {}", file, ctx.error));
    throw SceneError(fmt::format("{}: {}", file, firstLine(err)));
  }
  forwardWarnings(warn, file, options);
  return parsed;
}

uint64_t tinygltfElementBytes(std::string_view array) {
  static const std::map<std::string_view, uint64_t> bytes = {
      {"accessors", sizeof(tinygltf::Accessor)}, {"animations", sizeof(tinygltf::Animation)},
      {"buffers", sizeof(tinygltf::Buffer)},     {"bufferViews", sizeof(tinygltf::BufferView)},
      {"cameras", sizeof(tinygltf::Camera)},     {"images", sizeof(tinygltf::Image)},
      {"materials", sizeof(tinygltf::Material)}, {"meshes", sizeof(tinygltf::Mesh)},
      {"nodes", sizeof(tinygltf::Node)},         {"samplers", sizeof(tinygltf::Sampler)},
      {"scenes", sizeof(tinygltf::Scene)},       {"skins", sizeof(tinygltf::Skin)},
      {"textures", sizeof(tinygltf::Texture)}};
  const auto it = bytes.find(array);
  return it != bytes.end() ? it->second : 32;
}

std::string decodeUri(const std::string& uri) { return tinygltf::dlib::urldecode(uri); }

}  // namespace penumbra::detail
