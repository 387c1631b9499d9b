// Resolves `#include "..."` in embedded OpenCL sources so that the device compiler never touches the disk.
#include "host/cl/embedded_sources.h"

#include <fmt/format.h>

#include <cstdlib>
#include <fstream>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>

namespace penumbra {
namespace {

std::optional<std::string> readOverride(std::string_view name) {
  const char* dir = std::getenv("PENUMBRA_KERNEL_DIR");
  if (dir == nullptr || *dir == '\0') return std::nullopt;
  std::ifstream in(std::string(dir) + "/" + std::string(name), std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string lookup(std::string_view name) {
  if (auto text = readOverride(name)) return *text;
  for (const EmbeddedSource& source : embeddedSources())
    if (source.name == name) return std::string(source.text);
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

void append(std::string_view name, std::set<std::string>& seen, std::string& out, int depth) {
  if (depth > 16) throw std::runtime_error(fmt::format("OpenCL source '{}': includes nest too deep", name));
  if (!seen.insert(std::string(name)).second) return;
  const std::string text = lookup(name);
  std::istringstream lines(text);
  std::string line;
  int number = 0;
  out += fmt::format("#line 1 \"{}\"\n", name);
  while (std::getline(lines, line)) {
    ++number;
    if (auto target = includeTarget(line)) {
      append(*target, seen, out, depth + 1);
      out += fmt::format("#line {} \"{}\"\n", number + 1, name);
    } else {
      out += line;
      out += '\n';
    }
  }
}

}  // namespace

std::string resolveKernelSource(std::string_view name) {
  std::set<std::string> seen;
  std::string out;
  append(name, seen, out, 0);
  return out;
}

}  // namespace penumbra
