// All-or-nothing file output that never destroys what it does not own. A regular file (or a new one) is written to a
// uniquely named sibling temp file, flushed to disk (fsync) and renamed over the target only once complete, so a failed
// or interrupted write never leaves a truncated file where a reader expects a good one (rename(2) within one
// directory is atomic on POSIX). A symlink is followed and its final target replaced, never the link itself. A
// character device or FIFO (/dev/null, /dev/stdout, a named pipe) is written in place; a directory, socket or block
// device is refused with a message naming the path (docs/robustness.md, Outputs).
#pragma once

#include <filesystem>
#include <fstream>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace penumbra {

// A write that the system refused: the message names the path and the reason; errorNumber() is errno (0 when none is
// known), so callers can tell a full disk (ENOSPC, EDQUOT) or a failing device (EIO) from a bad path.
class OutputError : public std::runtime_error {
 public:
  OutputError(const std::string& what, int errorNumber) : std::runtime_error(what), errorNumber_(errorNumber) {}
  int errorNumber() const { return errorNumber_; }

 private:
  int errorNumber_;
};

// Whether errno `e` says the storage, not the job, failed: no space, a quota, an I/O error. Running again later (or
// elsewhere) can succeed.
bool isStorageError(int e);

// How an output path is written, from what is at the path now (symlinks followed).
enum class OutputMode {
  kReplace,  // a regular file, or nothing yet: temp file, fsync, rename over `path`
  kInPlace,  // a character device or FIFO: opened and written directly, never renamed over
};

struct OutputTarget {
  std::filesystem::path path;  // where the bytes go: the symlink chain's last target (the path itself if no link)
  OutputMode mode = OutputMode::kReplace;
};

// Resolves `requested` for writing. Throws std::runtime_error naming `requested` for an empty path, a directory,
// a socket, a block device, or a symlink chain that loops or is longer than 40 links.
OutputTarget resolveOutputTarget(const std::filesystem::path& requested);

class PendingFile {
 public:
  // Resolves the target (resolveOutputTarget) and opens the temp file beside it, or the device/FIFO itself. Throws
  // std::runtime_error naming `target` and the system's reason (missing directory, permission, not a directory,
  // a refused kind of file, ...).
  explicit PendingFile(std::filesystem::path target);
  // Removes the temp file unless commit() succeeded. Never throws.
  ~PendingFile();
  PendingFile(const PendingFile&) = delete;
  PendingFile& operator=(const PendingFile&) = delete;

  std::ofstream& stream() { return stream_; }
  // Writes `size` bytes to stream(), keeping the system's reason (errno) of a failure for finish()'s message: a
  // device's error (/dev/full: ENOSPC) surfaces in the write, and later calls may change errno. False on failure.
  bool write(const void* data, size_t size);
  // The path as the caller named it (messages name this one).
  const std::filesystem::path& target() const { return target_; }
  const std::filesystem::path& tempPath() const { return temp_; }

  // Flushes and closes the stream, checks that every byte reached the file and syncs it to disk; no rename yet.
  // Throws std::runtime_error naming the target on failure (the temp file is removed). Idempotent.
  void finish();
  // finish(), then renames the temp file over the resolved target (kReplace). Throws std::runtime_error naming the
  // target on failure (the temp file is removed).
  void commit();

 private:
  std::filesystem::path target_;
  OutputTarget resolved_;
  std::filesystem::path temp_;  // empty for kInPlace
  std::ofstream stream_;
  int writeError_ = 0;  // errno of the first failed write()
  bool finished_ = false;
  bool committed_ = false;
};

// Files that are written together and replace their old versions together (an EXR and its PNG preview): each is
// finished (written, flushed, synced) as it is added, and commit() renames them in the order they were added, so a
// failure while writing any of them (a full disk) leaves every old file as it was. Destroyed uncommitted, it removes
// the temp files.
class CommitGroup {
 public:
  // Finishes `file` (PendingFile::finish) and holds it until commit(). Throws as finish() does.
  void add(std::unique_ptr<PendingFile> file);
  void commit();

 private:
  std::vector<std::unique_ptr<PendingFile>> files_;
};

// Finishes `file` and commits it now, or hands it to `group` (when not null) for a later commit together.
void commitOrDefer(std::unique_ptr<PendingFile> file, CommitGroup* group);

// Writes `bytes` to `target` through a PendingFile.
void writeFileAtomically(const std::filesystem::path& target, std::span<const unsigned char> bytes);
void writeFileAtomically(const std::filesystem::path& target, std::string_view text);

}  // namespace penumbra
