// PendingFile: temp file "<name>.tmp-<random>" beside the target, renamed over it on commit and
// removed otherwise. Errors carry the target path and strerror(errno) of the failing call.
#include "host/io/atomic_file.h"

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

std::filesystem::path tempPathFor(const std::filesystem::path& target) {
  // Random rather than pid-based so two threads of one process writing the same target never
  // share a temp file.
  std::random_device entropy;
  const unsigned long long tag = (static_cast<unsigned long long>(entropy()) << 32) ^ entropy();
  std::filesystem::path temp = target;
  temp += fmt::format(".tmp-{:016x}", tag);
  return temp;
}

std::string displayPath(const std::filesystem::path& path) { return path.string(); }

}  // namespace

PendingFile::PendingFile(std::filesystem::path target) : target_(std::move(target)), temp_(tempPathFor(target_)) {
  if (target_.empty()) throw std::runtime_error("cannot write a file with an empty path");
  errno = 0;
  stream_.open(temp_, std::ios::binary | std::ios::trunc);
  if (!stream_.is_open()) {
    const int error = errno;
    throw std::runtime_error(fmt::format("{}: cannot create file: {}", displayPath(target_),
                                         error != 0 ? std::strerror(error) : "unknown error"));
  }
}

PendingFile::~PendingFile() {
  if (committed_) return;
  if (stream_.is_open()) stream_.close();
  std::error_code ignored;
  std::filesystem::remove(temp_, ignored);
}

void PendingFile::commit() {
  errno = 0;
  stream_.flush();
  const bool flushed = stream_.good();
  stream_.close();
  if (!flushed || stream_.fail()) {
    const int error = errno;
    throw std::runtime_error(
        fmt::format("{}: write failed: {}", displayPath(target_), error != 0 ? std::strerror(error) : "stream error"));
  }
  std::error_code error;
  std::filesystem::rename(temp_, target_, error);
  if (error)
    throw std::runtime_error(fmt::format("{}: cannot replace file: {}", displayPath(target_), error.message()));
  committed_ = true;
}

void writeFileAtomically(const std::filesystem::path& target, std::span<const unsigned char> bytes) {
  PendingFile file(target);
  file.stream().write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  file.commit();
}

}  // namespace penumbra
