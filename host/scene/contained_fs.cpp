// Containment and size checks for every file a scene load reads. Inside a model: lexical checks first (scheme,
// absolute, ".."), then the canonical path must still lie under the canonical root, which catches symlinks.
// A scene file's model paths are only resolved (the scene file is the user's own, like the command line).
#include "host/scene/contained_fs.h"

#include <algorithm>
#include <cctype>
#include <fstream>

#include <fmt/format.h>

namespace penumbra::detail {
namespace {

namespace fs = std::filesystem;

// "http:", "file:", "C:" ...: RFC 3986 scheme = ALPHA *( ALPHA / DIGIT / "+" / "-" / "." ) ":".
bool hasScheme(std::string_view s) {
  const size_t colon = s.find(':');
  if (colon == std::string_view::npos || colon == 0) return false;
  if (!std::isalpha(static_cast<unsigned char>(s[0]))) return false;
  return std::all_of(s.begin(), s.begin() + static_cast<std::ptrdiff_t>(colon), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '+' || c == '-' || c == '.';
  });
}

bool hasDotDot(std::string_view s) {
  size_t start = 0;
  while (start <= s.size()) {
    const size_t end = std::min(s.find_first_of("/\\", start), s.size());
    if (s.substr(start, end - start) == "..") return true;
    start = end + 1;
  }
  return false;
}

bool isUnder(const fs::path& root, const fs::path& p) {
  auto [r, q] = std::mismatch(root.begin(), root.end(), p.begin(), p.end());
  return r == root.end() && q != p.end();
}

}  // namespace

fs::path resolveInside(const fs::path& root, std::string_view relative) {
  const std::string quoted = fmt::format("\"{}\"", visible(relative));
  if (relative.empty()) throw SceneError("empty path");
  if (relative.find('\0') != std::string_view::npos) throw SceneError(quoted + ": path contains a NUL byte");
  if (hasScheme(relative)) throw SceneError(quoted + ": URI schemes and drive letters are not allowed");
  if (relative.front() == '/' || relative.front() == '\\')
    throw SceneError(quoted + ": absolute paths are not allowed (paths are relative to the scene's folder)");
  // ".." is a legal URI segment: refused only where the path, read lexically, leaves the folder (then resolved, with
  // links, and checked again below).
  if (hasDotDot(relative) && !isUnder(root, (root / fs::path(std::string(relative))).lexically_normal()))
    throw SceneError(quoted + ": its \"..\" components leave the scene's folder");
  std::error_code ec;
  const fs::path resolved = fs::canonical(root / fs::path(std::string(relative)), ec);
  if (ec) throw SceneError(fmt::format("{}: file not found in {}", quoted, root.string()));
  if (!isUnder(root, resolved))
    throw SceneError(
        fmt::format("{}: resolves to {}, outside the scene's folder {}", quoted, resolved.string(), root.string()));
  if (!fs::is_regular_file(resolved, ec)) throw SceneError(quoted + ": not a regular file");
  return resolved;
}

fs::path resolveSceneModel(const fs::path& folder, std::string_view path) {
  const std::string quoted = fmt::format("\"{}\"", visible(path));
  if (path.empty()) throw SceneError("empty path");
  if (path.find('\0') != std::string_view::npos) throw SceneError(quoted + ": path contains a NUL byte");
  if (hasScheme(path)) throw SceneError(quoted + ": URI schemes are not allowed (give a file path)");
  const fs::path named(std::string{path});
  const fs::path joined = named.is_absolute() ? named : folder / named;
  std::error_code ec;
  const fs::path resolved = fs::canonical(joined, ec);  // symlinks resolved before "..", as the system does
  if (ec)
    throw SceneError(fmt::format("{}: file not found (looked for {})", quoted, joined.lexically_normal().string()));
  if (!fs::is_regular_file(resolved, ec)) throw SceneError(quoted + ": not a regular file");
  return resolved;
}

fs::path resolveUserFile(const std::string& path) {
  std::error_code ec;
  const fs::path resolved = fs::canonical(fs::path(path), ec);
  // The system's reason, not always "not found": a symlink loop (ELOOP), a permission, a path through a file.
  if (ec == std::errc::no_such_file_or_directory) throw SceneError(fmt::format("{}: file not found", path));
  if (ec) throw SceneError(fmt::format("{}: cannot open: {}", path, ec.message()));
  if (fs::is_directory(resolved, ec)) throw SceneError(fmt::format("{}: is a directory, not a scene file", path));
  if (!fs::is_regular_file(resolved, ec)) throw SceneError(fmt::format("{}: not a regular file", path));
  return resolved;
}

std::vector<unsigned char> FileReader::read(const fs::path& path) {
  std::error_code ec;
  const uint64_t size = fs::file_size(path, ec);
  if (ec) throw SceneError(fmt::format("cannot read {}: {}", path.string(), ec.message()));
  if (size > maxFileBytes_)
    throw SceneError(
        fmt::format("{} is {} bytes, over the limit of {} bytes per file", path.string(), size, maxFileBytes_));
  if (size > remainingBytes_)
    throw SceneError(
        fmt::format("{}: reading its {} bytes would exceed the limit on bytes read per load", path.string(), size));
  std::ifstream in(path, std::ios::binary);
  std::vector<unsigned char> data(static_cast<size_t>(size));
  if (!in || !in.read(reinterpret_cast<char*>(data.data()), static_cast<std::streamsize>(size)) ||
      in.peek() != std::char_traits<char>::eof())
    throw SceneError(fmt::format("cannot read {} (changed while reading?)", path.string()));
  remainingBytes_ -= size;
  if (onRead_) onRead_(path, data);
  return data;
}

void FileReader::claimTextureBytes(uint64_t bytes, const std::string& what) {
  if (bytes > remainingTextureBytes_)
    throw SceneError(
        fmt::format("{}: its {} alpha texels would exceed the limit of {} bytes of decoded textures per "
                    "load ({} used by earlier textures)",
                    what, bytes, maxTextureBytes_, maxTextureBytes_ - remainingTextureBytes_));
  remainingTextureBytes_ -= bytes;
}

}  // namespace penumbra::detail
