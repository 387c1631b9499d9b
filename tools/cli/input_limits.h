// The batch tools' bounds on what they read whole (bytes), by what the file holds: the CLI's policy, applied through
// host/io/bounded_read.h's readBoundedFile (docs/robustness.md, Limits).
#pragma once

#include <cstdint>

namespace penumbra {

inline constexpr uint64_t kMaxManifestBytes = uint64_t{256} << 20;   // a million jobs of ~250 bytes
inline constexpr uint64_t kMaxStatusLogBytes = uint64_t{256} << 20;  // per status log (one per shard)
inline constexpr uint64_t kMaxSweepBytes = uint64_t{16} << 20;
inline constexpr uint64_t kMaxCameraPathBytes = uint64_t{64} << 20;

}  // namespace penumbra
