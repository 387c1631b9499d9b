// Reading a whole input file with a bound, whatever sits at the path: a regular file, a FIFO (process substitution,
// `<(...)`) or a character device (`/dev/stdin`) is read to its end or until it passes the bound, so `/dev/zero`
// fails at once instead of filling memory; a FIFO nobody writes to reads as empty instead of blocking forever; a
// directory is refused. The batch tools read their manifests, sweeps, status logs and camera paths through it, with
// the bounds of tools/cli/input_limits.h (docs/robustness.md, Limits).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

namespace penumbra {

// The bytes of `path`, at most `maxBytes` of them. Throws std::runtime_error starting with the path: "PATH: cannot
// read WHAT: REASON" (missing, permission, a directory, a socket) or "PATH: WHAT is over the limit of N bytes".
std::string readBoundedFile(const std::filesystem::path& path, uint64_t maxBytes, const std::string& what);

}  // namespace penumbra
