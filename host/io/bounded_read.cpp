// readBoundedFile: open(2) with O_NONBLOCK (so that opening a FIFO without a writer returns at once), fstat to refuse
// what is no file, then blocking reads of up to the bound plus one byte.
#include "host/io/bounded_read.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include <fmt/format.h>

namespace penumbra {
namespace {

class Fd {  // closes on every path out
 public:
  explicit Fd(int fd) : fd_(fd) {}
  ~Fd() {
    if (fd_ >= 0) ::close(fd_);
  }
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  int get() const { return fd_; }

 private:
  int fd_;
};

}  // namespace

std::string readBoundedFile(const std::filesystem::path& path, uint64_t maxBytes, const std::string& what) {
  const auto fail = [&](const std::string& why) {
    throw std::runtime_error(fmt::format("{}: cannot read {}: {}", path.string(), what, why));
  };
  const Fd fd(::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK));
  if (fd.get() < 0) fail(std::strerror(errno));
  struct stat st {};
  if (::fstat(fd.get(), &st) != 0) fail(std::strerror(errno));
  if (S_ISDIR(st.st_mode)) fail("is a directory");
  if (!S_ISREG(st.st_mode) && !S_ISFIFO(st.st_mode) && !S_ISCHR(st.st_mode)) fail("not a file, FIFO or device");
  if (S_ISREG(st.st_mode) && static_cast<uint64_t>(st.st_size) > maxBytes)
    throw std::runtime_error(fmt::format("{}: {} is {} bytes, over the limit of {} bytes", path.string(), what,
                                         static_cast<uint64_t>(st.st_size), maxBytes));
  // Blocking reads from here on: a FIFO waits for its writer's data, and reads as empty when it has none.
  const int flags = ::fcntl(fd.get(), F_GETFL);
  if (flags < 0 || ::fcntl(fd.get(), F_SETFL, flags & ~O_NONBLOCK) != 0) fail(std::strerror(errno));
  std::string text;
  char chunk[1 << 16];
  for (;;) {
    const ssize_t n = ::read(fd.get(), chunk, sizeof(chunk));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) fail(std::strerror(errno));
    if (n == 0) break;
    if (text.size() + static_cast<uint64_t>(n) > maxBytes)
      throw std::runtime_error(
          fmt::format("{}: {} is over the limit of {} bytes (read stopped there)", path.string(), what, maxBytes));
    text.append(chunk, static_cast<size_t>(n));
  }
  return text;
}

}  // namespace penumbra
