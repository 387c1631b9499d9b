// Reading a whole input file with a bound, whatever sits at the path: a regular file, a FIFO (process substitution,
// `<(...)`) or a character device (`/dev/stdin`) is read to its end or until it passes the bound, so `/dev/zero`
// fails at once instead of filling memory; a FIFO nobody writes to reads as empty instead of blocking forever; a
// directory is refused. The batch tools' manifests, sweeps, status logs and camera paths (docs/robustness.md, Limits).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

namespace penumbra {

// Every input read through readBoundedFile, by what it holds (bytes).
inline constexpr uint64_t kMaxManifestBytes = uint64_t{256} << 20;  // a million jobs of ~250 bytes
inline constexpr uint64_t kMaxStatusLogBytes = uint64_t{256} << 20;  // per status log (one per shard)
inline constexpr uint64_t kMaxSweepBytes = uint64_t{16} << 20;
inline constexpr uint64_t kMaxCameraPathBytes = uint64_t{64} << 20;

// The bytes of `path`, at most `maxBytes` of them. Throws std::runtime_error starting with the path: "PATH: cannot
// read WHAT: REASON" (missing, permission, a directory, a socket) or "PATH: WHAT is over the limit of N bytes".
std::string readBoundedFile(const std::filesystem::path& path, uint64_t maxBytes, const std::string& what);

}  // namespace penumbra
