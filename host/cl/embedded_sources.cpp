// Resolves `#include "..."` in embedded OpenCL sources so that the device compiler never touches the disk
// (or, with PENUMBRA_KERNEL_DIR, in the sources of that folder, every one of which must be there).
#include "host/cl/embedded_sources.h"

#include <fmt/format.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace penumbra {
namespace {

// With PENUMBRA_KERNEL_DIR set, every source must come from that folder: a missing file is an error, never a
// silent fall-back to the embedded copy (which would run code other than the one being edited).
std::optional<std::string> readOverride(std::string_view name) {
  const char* dir = std::getenv("PENUMBRA_KERNEL_DIR");
  if (dir == nullptr || *dir == '\0') return std::nullopt;
  const std::filesystem::path folder(dir), file = folder / std::string(name);
  std::error_code error;
  if (!std::filesystem::is_directory(folder, error))
    throw std::runtime_error(
        fmt::format("PENUMBRA_KERNEL_DIR={}: not a folder (unset it to use the built-in kernels)", dir));
  std::ifstream in(file, std::ios::binary);
  if (!std::filesystem::is_regular_file(file, error) || !in)
    throw std::runtime_error(fmt::format(
        "PENUMBRA_KERNEL_DIR={}: the folder has no {} (point it at a source tree's root, or unset it to use the "
        "built-in kernels)",
        dir, name));
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

const EmbeddedSource* find(std::span<const EmbeddedSource> table, std::string_view name) {
  for (const EmbeddedSource& source : table)
    if (source.name == name) return &source;
  return nullptr;
}

std::string lookup(std::string_view name, const SourceTables& more) {
  if (auto text = readOverride(name)) return *text;
  if (const EmbeddedSource* source = find(embeddedSources(), name)) return std::string(source->text);
  for (std::span<const EmbeddedSource> table : more)
    if (const EmbeddedSource* source = find(table, name)) return std::string(source->text);
  throw std::runtime_error(fmt::format("OpenCL source '{}' is not embedded in this build", name));
}

// Returns the include target of a line `#include "x"`, or nothing.
std::optional<std::string> includeTarget(std::string_view line) {
  size_t pos = line.find_first_not_of(" \t");
  if (pos == std::string_view::npos || line[pos] != '#') return std::nullopt;
  pos = line.find_first_not_of(" \t", pos + 1);
  if (pos == std::string_view::npos || line.substr(pos, 7) != "include") return std::nullopt;
  size_t open = line.find('"', pos + 7);
  size_t close = open == std::string_view::npos ? open : line.find('"', open + 1);
  if (close == std::string_view::npos) return std::nullopt;
  return std::string(line.substr(open + 1, close - open - 1));
}

void append(std::string_view name, const SourceTables& more, std::set<std::string>& seen, std::string& out,
            int depth) {
  if (depth > 16) throw std::runtime_error(fmt::format("OpenCL source '{}': includes nest too deep", name));
  if (!seen.insert(std::string(name)).second) return;
  const std::string text = lookup(name, more);
  std::istringstream lines(text);
  std::string line;
  int number = 0;
  out += fmt::format("#line 1 \"{}\"\n", name);
  while (std::getline(lines, line)) {
    ++number;
    if (auto target = includeTarget(line)) {
      append(*target, more, seen, out, depth + 1);
      out += fmt::format("#line {} \"{}\"\n", number + 1, name);
    } else {
      out += line;
      out += '\n';
    }
  }
}

}  // namespace

void checkNewSources(std::span<const EmbeddedSource> table, const SourceTables& tables) {
  for (const EmbeddedSource& source : table) {
    bool taken = find(embeddedSources(), source.name) != nullptr;
    for (std::span<const EmbeddedSource> other : tables) taken = taken || find(other, source.name) != nullptr;
    if (taken) throw std::logic_error(fmt::format("OpenCL source '{}' is embedded twice", source.name));
  }
}

std::string resolveKernelSource(std::string_view name, const SourceTables& more) {
  std::set<std::string> seen;
  std::string out;
  append(name, more, seen, out, 0);
  return out;
}

}  // namespace penumbra
