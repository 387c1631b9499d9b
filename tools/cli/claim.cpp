// Claims: O_CREAT | O_EXCL creates them; a stale one is first renamed aside (only one run can rename it), then
// checked again (a run that took it over in between got it back) before a fresh claim is created.
#include "tools/cli/claim.h"

#include <fcntl.h>
#include <fmt/chrono.h>
#include <fmt/format.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "host/cl/context.h"
#include "tools/cli/job_status.h"

namespace penumbra::cli {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// 64-bit FNV-1a of the output path: the claim's file name (stable across runs and machines).
std::string claimName(const std::string& output) { return fmt::format("{:016x}.claim", fnv1a64(output)); }

fs::path claimPath(const fs::path& outDir, const std::string& output) {
  return statusFolder(outDir) / "claims" / claimName(output);
}

// Field 22 of /proc/PID/stat (after the parenthesised command, which may hold spaces): 0 when it cannot be read.
unsigned long long startTime(long pid) {
  std::ifstream in(fmt::format("/proc/{}/stat", pid));
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const size_t close = text.rfind(')');
  if (close == std::string::npos) return 0;
  std::istringstream fields(text.substr(close + 2));
  std::string field;
  for (int i = 3; i <= 22 && fields >> field; ++i)
    if (i == 22) return std::strtoull(field.c_str(), nullptr, 10);
  return 0;
}

ClaimOwner self(const std::string& job) {
  const auto now = std::chrono::system_clock::now();
  return {hostName(), static_cast<long>(getpid()), startTime(getpid()), job,
          fmt::format("{:%Y-%m-%dT%H:%M:%S}Z", fmt::gmtime(std::chrono::system_clock::to_time_t(now)))};
}

std::optional<ClaimOwner> readClaim(const fs::path& path) {
  std::ifstream in(path);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  try {
    const json j = json::parse(text);
    return ClaimOwner{j.at("host"), j.at("pid"), j.at("start"), j.value("job", ""), j.value("time", "")};
  } catch (const json::exception&) {
    return std::nullopt;  // cut short by a crash between creating and writing it: nobody's
  }
}

// Live: this host's owner still runs (the same pid with the same start time); another host's within the lease of
// the claim file's age.
bool live(const ClaimOwner& owner, const fs::path& path, double leaseSeconds) {
  if (owner.host == hostName()) {
    if (kill(static_cast<pid_t>(owner.pid), 0) != 0 && errno != EPERM) return false;
    return startTime(owner.pid) == owner.start;
  }
  struct stat st {};
  if (stat(path.c_str(), &st) != 0) return false;
  return static_cast<double>(time(nullptr) - st.st_mtime) < leaseSeconds;
}

// Creates the claim file; false when it exists already.
bool create(const fs::path& path, const ClaimOwner& owner) {
  const int fd = open(path.c_str(), O_CREAT | O_EXCL | O_WRONLY, 0644);
  if (fd < 0) {
    if (errno == EEXIST) return false;
    throw std::runtime_error(fmt::format("{}: cannot create the claim: {}", path.string(), std::strerror(errno)));
  }
  const std::string text = json{{"host", owner.host}, {"pid", owner.pid}, {"start", owner.start},
                                {"job", owner.job},   {"time", owner.time}}
                               .dump() +
                           "\n";
  const bool written = write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size());
  close(fd);
  if (!written) {
    unlink(path.c_str());
    throw std::runtime_error(fmt::format("{}: cannot write the claim", path.string()));
  }
  return true;
}

}  // namespace

std::optional<Claim> Claim::take(const fs::path& outDir, const std::string& output, const std::string& job,
                                 double leaseSeconds, ClaimOwner& holder) {
  const fs::path path = claimPath(outDir, output);
  std::error_code error;
  fs::create_directories(path.parent_path(), error);
  const ClaimOwner me = self(job);
  for (int attempt = 0; attempt < 3; ++attempt) {
    if (create(path, me)) return Claim(path);
    const std::optional<ClaimOwner> owner = readClaim(path);
    if (owner && live(*owner, path, leaseSeconds)) return holder = *owner, std::nullopt;
    // Stale: rename it aside (one run wins), then make sure what was renamed was the stale claim.
    const fs::path aside = path.string() + fmt::format(".stale-{}", me.pid);
    if (rename(path.c_str(), aside.c_str()) != 0) continue;  // another run moved or replaced it: look again
    const std::optional<ClaimOwner> moved = readClaim(aside);
    if (moved && live(*moved, aside, leaseSeconds)) {  // a fresh claim taken over in between: give it back
      if (link(aside.c_str(), path.c_str()) == 0) unlink(aside.c_str());
      return holder = *moved, std::nullopt;
    }
    unlink(aside.c_str());
  }
  if (const std::optional<ClaimOwner> owner = readClaim(path)) return holder = *owner, std::nullopt;
  throw std::runtime_error(fmt::format("{}: cannot take the claim", path.string()));
}

Claim::Claim(Claim&& other) noexcept : path_(std::move(other.path_)) { other.path_.clear(); }

Claim& Claim::operator=(Claim&& other) noexcept {
  if (this != &other) {
    if (!path_.empty()) unlink(path_.c_str());
    path_ = std::move(other.path_);
    other.path_.clear();
  }
  return *this;
}

Claim::~Claim() {
  if (!path_.empty()) unlink(path_.c_str());
}

std::optional<ClaimOwner> liveClaim(const fs::path& outDir, const std::string& output, double leaseSeconds) {
  const fs::path path = claimPath(outDir, output);
  std::optional<ClaimOwner> owner = readClaim(path);
  if (owner && !live(*owner, path, leaseSeconds)) owner.reset();
  return owner;
}

}  // namespace penumbra::cli
