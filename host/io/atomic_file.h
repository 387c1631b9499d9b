// All-or-nothing file output: data goes to a uniquely named sibling temp file that is renamed over
// the target only once it is complete, so a failed or interrupted write never leaves a truncated
// image where a reader expects a good one (rename(2) within one directory is atomic on POSIX).
#pragma once

#include <filesystem>
#include <fstream>
#include <span>

namespace penumbra {

class PendingFile {
 public:
  // Creates and opens the temp file next to `target`. Throws std::runtime_error naming `target`
  // and the system's reason (missing directory, permission, not a directory, ...).
  explicit PendingFile(std::filesystem::path target);
  // Removes the temp file unless commit() succeeded. Never throws.
  ~PendingFile();
  PendingFile(const PendingFile&) = delete;
  PendingFile& operator=(const PendingFile&) = delete;

  std::ofstream& stream() { return stream_; }
  const std::filesystem::path& target() const { return target_; }
  const std::filesystem::path& tempPath() const { return temp_; }

  // Flushes and closes the stream, checks that every byte reached the file, then renames it over
  // the target. Throws std::runtime_error naming the target on failure (the temp file is removed).
  void commit();

 private:
  std::filesystem::path target_;
  std::filesystem::path temp_;
  std::ofstream stream_;
  bool committed_ = false;
};

// Writes `bytes` to `target` through a PendingFile.
void writeFileAtomically(const std::filesystem::path& target, std::span<const unsigned char> bytes);

}  // namespace penumbra
