// PendingFile: temp file "<name>.tmp-<random>" beside the resolved target, fsync'd and renamed over it on commit and
// removed otherwise; devices and FIFOs written in place. Errors carry the target path and strerror(errno) of the
// failing call.
#include "host/io/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <random>
#include <stdexcept>
#include <string>
#include <system_error>
#include <utility>

#include <fmt/format.h>

namespace penumbra {
namespace {

constexpr int kMaxSymlinks = 40;  // Linux's own limit on a path's symlinks (ELOOP)

std::filesystem::path tempPathFor(const std::filesystem::path& target) {
  // Random rather than pid-based so two threads of one process writing the same target never
  // share a temp file.
  std::random_device entropy;
  const unsigned long long tag = (static_cast<unsigned long long>(entropy()) << 32) ^ entropy();
  std::filesystem::path temp = target;
  temp += fmt::format(".tmp-{:016x}", tag);
  return temp;
}

std::string reason(int error, const char* fallback) { return error != 0 ? std::strerror(error) : fallback; }

[[noreturn]] void refuse(const std::filesystem::path& requested, const std::string& why) {
  throw std::runtime_error(fmt::format("{}: {}", requested.string(), why));
}

// fsync(2) of a file or directory by path: false with errno set when it cannot be opened or synced.
bool syncPath(const std::filesystem::path& path, int flags) {
  const int fd = ::open(path.c_str(), flags | O_CLOEXEC);
  if (fd < 0) return false;
  const bool ok = ::fsync(fd) == 0;
  const int error = errno;
  ::close(fd);
  errno = error;
  return ok;
}

}  // namespace

OutputTarget resolveOutputTarget(const std::filesystem::path& requested) {
  if (requested.empty()) throw std::runtime_error("cannot write a file with an empty path");
  std::filesystem::path path = requested;
  for (int links = 0;; ++links) {
    struct stat st {};
    if (::lstat(path.c_str(), &st) != 0) return {path, OutputMode::kReplace};  // new (or the open names the reason)
    if (S_ISLNK(st.st_mode)) {
      if (links == kMaxSymlinks) refuse(requested, "too many levels of symbolic links");
      std::error_code error;
      const std::filesystem::path link = std::filesystem::read_symlink(path, error);
      if (error) refuse(requested, "cannot read symbolic link: " + error.message());
      path = link.is_absolute() ? link : path.parent_path() / link;
      continue;
    }
    if (S_ISREG(st.st_mode)) return {path, OutputMode::kReplace};
    if (S_ISCHR(st.st_mode) || S_ISFIFO(st.st_mode)) return {path, OutputMode::kInPlace};
    if (S_ISDIR(st.st_mode)) refuse(requested, "is a directory (name a file in it)");
    if (S_ISBLK(st.st_mode)) refuse(requested, "is a block device (refusing to write an image over it)");
    if (S_ISSOCK(st.st_mode)) refuse(requested, "is a socket (cannot be written as a file)");
    refuse(requested, "is not a regular file, character device or FIFO");
  }
}

bool isStorageError(int e) { return e == ENOSPC || e == EDQUOT || e == EIO; }

PendingFile::PendingFile(std::filesystem::path target)
    : target_(std::move(target)), resolved_(resolveOutputTarget(target_)) {
  if (resolved_.mode == OutputMode::kReplace) temp_ = tempPathFor(resolved_.path);
  const std::filesystem::path& opened = temp_.empty() ? resolved_.path : temp_;
  errno = 0;
  stream_.open(opened, std::ios::binary | std::ios::trunc);
  if (!stream_.is_open()) {
    const int error = errno;
    throw OutputError(fmt::format("{}: cannot {} file: {}", target_.string(), temp_.empty() ? "open" : "create",
                                  reason(error, "unknown error")),
                      error);
  }
}

PendingFile::~PendingFile() {
  if (committed_) return;
  if (stream_.is_open()) stream_.close();
  if (temp_.empty()) return;
  std::error_code ignored;
  std::filesystem::remove(temp_, ignored);
}

bool PendingFile::write(const void* data, size_t size) {
  errno = 0;
  if (stream_.write(static_cast<const char*>(data), static_cast<std::streamsize>(size))) return true;
  if (writeError_ == 0) writeError_ = errno;
  return false;
}

void PendingFile::finish() {
  if (finished_) return;
  errno = 0;
  stream_.flush();
  const bool flushed = stream_.good();
  int error = writeError_ != 0 ? writeError_ : errno;
  stream_.close();
  if (error == 0) error = errno;
  if (!flushed || stream_.fail())
    throw OutputError(fmt::format("{}: write failed: {}", target_.string(), reason(error, "stream error")), error);
  if (!temp_.empty()) {
    if (!syncPath(temp_, O_RDONLY)) {
      const int syncError = errno;
      throw OutputError(fmt::format("{}: cannot sync to disk: {}", target_.string(), reason(syncError, "?")),
                        syncError);
    }
    // A replaced file keeps its permissions (a new one gets the umask's).
    std::error_code old;
    const auto status = std::filesystem::status(resolved_.path, old);
    if (!old && std::filesystem::is_regular_file(status))
      std::filesystem::permissions(temp_, status.permissions(), old);
  }
  finished_ = true;
}

void PendingFile::commit() {
  finish();
  if (!temp_.empty()) {
    std::error_code error;
    std::filesystem::rename(temp_, resolved_.path, error);
    if (error)
      throw OutputError(fmt::format("{}: cannot replace file: {}", target_.string(), error.message()), error.value());
    // The rename itself on disk: best effort (some file systems refuse a directory's fsync).
    const std::filesystem::path parent = resolved_.path.has_parent_path() ? resolved_.path.parent_path() : ".";
    syncPath(parent, O_RDONLY | O_DIRECTORY);
  }
  committed_ = true;
}

void CommitGroup::add(std::unique_ptr<PendingFile> file) {
  file->finish();
  files_.push_back(std::move(file));
}

void CommitGroup::commit() {
  for (auto& file : files_) file->commit();
  files_.clear();
}

void commitOrDefer(std::unique_ptr<PendingFile> file, CommitGroup* group) {
  if (group != nullptr)
    group->add(std::move(file));
  else
    file->commit();
}

void writeFileAtomically(const std::filesystem::path& target, std::span<const unsigned char> bytes) {
  PendingFile file(target);
  file.write(bytes.data(), bytes.size());
  file.commit();  // throws naming the write's failure
}

void writeFileAtomically(const std::filesystem::path& target, std::string_view text) {
  writeFileAtomically(target, {reinterpret_cast<const unsigned char*>(text.data()), text.size()});
}

}  // namespace penumbra
