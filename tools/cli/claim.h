// Per-output claims, so that runs overlapping on one --out (a shard submitted twice, a resubmission while the first
// array still runs, several people's manifests) render each job once and never delete each other's temporaries.
// A claim is DIR/penumbra-status/claims/<hash of the output path>.claim, created with O_CREAT | O_EXCL, naming its
// owner: host, pid and that process's start time, the job and when it was taken. It is live while its owner runs: on
// this host, while that pid runs with that start time (a reused pid is not the owner); from another host, until the
// lease has passed since it was taken. A live claim makes another run leave the job to its owner; a stale one is
// taken over.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

namespace penumbra::cli {

struct ClaimOwner {
  std::string host;
  long pid = 0;
  unsigned long long start = 0;  // the process's start time (clock ticks after boot, /proc/PID/stat field 22)
  std::string job, time;         // the job's manifest line, when it was taken (UTC)
};

class Claim {
 public:
  // Claims `output` (relative to outDir) for `job`, or returns nothing and fills `holder` when a live claim is
  // someone else's. Throws std::runtime_error naming the claim file when it can be neither read nor created.
  static std::optional<Claim> take(const std::filesystem::path& outDir, const std::string& output,
                                   const std::string& job, double leaseSeconds, ClaimOwner& holder);
  Claim(Claim&& other) noexcept;
  Claim& operator=(Claim&& other) noexcept;  // releases this claim, takes the other's
  Claim(const Claim&) = delete;
  ~Claim();  // the claim file removed

 private:
  explicit Claim(std::filesystem::path path) : path_(std::move(path)) {}
  std::filesystem::path path_;  // empty once moved from
};

// The owner of a live claim on `output` now, if any (for stale temporaries: only those of unclaimed or stale outputs
// are removed; for `status`: a job being rendered).
std::optional<ClaimOwner> liveClaim(const std::filesystem::path& outDir, const std::string& output,
                                    double leaseSeconds);
inline bool claimIsLive(const std::filesystem::path& outDir, const std::string& output, double leaseSeconds) {
  return liveClaim(outDir, output, leaseSeconds).has_value();
}

// The lease `run` gives another host's claim unless --claim-lease says otherwise (seconds).
inline constexpr double kDefaultClaimLeaseSeconds = 6 * 3600;

}  // namespace penumbra::cli
