// Tests of host/io/atomic_file.h: what sits at an output path decides how it is written. A regular file is replaced
// atomically (keeping its permissions), a symlink is written through (the link stays), a FIFO or character device is
// written in place and stays what it was, a directory, socket or symlink loop is refused, a write error (/dev/full)
// is reported, and a CommitGroup that fails before its commit leaves every old file as it was.
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <future>
#include <iterator>
#include <memory>
#include <stdexcept>
#include <string>

#include "host/io/atomic_file.h"
#include "tests/support/temp_dir.h"

namespace penumbra {
namespace io_atomic_file_test {

namespace fs = std::filesystem;

std::string contents(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void put(const fs::path& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

int leftovers(const fs::path& dir) {  // temp files a write left behind
  int n = 0;
  for (const auto& entry : fs::directory_iterator(dir)) n += entry.path().string().find(".tmp-") != std::string::npos;
  return n;
}

template <class F>
std::string errorOf(F&& f) {
  try {
    f();
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(AtomicFile, ReplacesARegularFileAndKeepsItsPermissions) {
  test::TempDir dir;
  const fs::path file = dir.path() / "out.csv";
  put(file, "old");
  fs::permissions(file, fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
  writeFileAtomically(file, std::string_view("new"));
  EXPECT_EQ(contents(file), "new");
  EXPECT_EQ(fs::status(file).permissions(), fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
  EXPECT_EQ(leftovers(dir.path()), 0);
}

TEST(AtomicFile, WritesThroughSymlinksAndKeepsThem) {
  test::TempDir dir;
  fs::create_directories(dir.path() / "real");
  put(dir.path() / "real" / "target.csv", "old");
  fs::create_symlink("real/target.csv", dir.path() / "hop");   // relative to the link's folder
  fs::create_symlink(dir.path() / "hop", dir.path() / "link");  // a chain of two
  writeFileAtomically(dir.path() / "link", std::string_view("new"));
  EXPECT_TRUE(fs::is_symlink(dir.path() / "link"));
  EXPECT_TRUE(fs::is_symlink(dir.path() / "hop"));
  EXPECT_EQ(contents(dir.path() / "real" / "target.csv"), "new");
  // A dangling link: its target is created, the link kept.
  fs::create_symlink("made.csv", dir.path() / "dangling");
  writeFileAtomically(dir.path() / "dangling", std::string_view("made"));
  EXPECT_TRUE(fs::is_symlink(dir.path() / "dangling"));
  EXPECT_EQ(contents(dir.path() / "made.csv"), "made");
}

TEST(AtomicFile, WritesAFifoInPlace) {
  test::TempDir dir;
  const fs::path fifo = dir.path() / "pipe.png";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0) << std::strerror(errno);
  ASSERT_EQ(resolveOutputTarget(fifo).mode, OutputMode::kInPlace);  // else the reader below would wait forever
  std::future<std::string> reader = std::async(std::launch::async, [&] { return contents(fifo); });
  writeFileAtomically(fifo, std::string_view("streamed"));
  EXPECT_EQ(reader.get(), "streamed");
  EXPECT_TRUE(fs::is_fifo(fifo));
  EXPECT_EQ(leftovers(dir.path()), 0);
}

TEST(AtomicFile, WritesCharacterDevicesInPlaceAndReportsTheirErrors) {
  ASSERT_TRUE(fs::is_character_file("/dev/null"));
  ASSERT_EQ(resolveOutputTarget("/dev/null").mode, OutputMode::kInPlace);  // before any write: never replace it
  writeFileAtomically("/dev/null", std::string_view("discarded"));
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
  if (!fs::is_character_file("/dev/full")) GTEST_SKIP() << "no /dev/full on this machine";
  ASSERT_EQ(resolveOutputTarget("/dev/full").mode, OutputMode::kInPlace);
  const std::string error = errorOf([] { writeFileAtomically("/dev/full", std::string(1 << 16, 'x')); });
  EXPECT_NE(error.find("/dev/full: write failed: No space left on device"), std::string::npos) << error;
  EXPECT_TRUE(fs::is_character_file("/dev/full"));
}

TEST(AtomicFile, RefusesDirectoriesSocketsAndLoops) {
  test::TempDir dir;
  EXPECT_NE(errorOf([&] { writeFileAtomically(dir.path(), std::string_view("x")); }).find("is a directory"),
            std::string::npos);
  const fs::path socketPath = dir.path() / "s.png";
  const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
  ASSERT_GE(fd, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  ASSERT_LT(socketPath.string().size(), sizeof(address.sun_path));
  std::strncpy(address.sun_path, socketPath.c_str(), sizeof(address.sun_path) - 1);
  ASSERT_EQ(::bind(fd, reinterpret_cast<const sockaddr*>(&address), sizeof(address)), 0) << std::strerror(errno);
  EXPECT_NE(errorOf([&] { writeFileAtomically(socketPath, std::string_view("x")); }).find("is a socket"),
            std::string::npos);
  EXPECT_TRUE(fs::is_socket(socketPath));
  ::close(fd);
  fs::create_symlink("b", dir.path() / "a");
  fs::create_symlink("a", dir.path() / "b");
  EXPECT_NE(errorOf([&] { writeFileAtomically(dir.path() / "a", std::string_view("x")); })
                .find("too many levels of symbolic links"),
            std::string::npos);
  EXPECT_NE(errorOf([] { writeFileAtomically("", std::string_view("x")); }).find("empty path"), std::string::npos);
}

TEST(AtomicFile, AGroupThatFailsBeforeItsCommitLeavesEveryOldFile) {
  test::TempDir dir;
  put(dir.path() / "a.exr", "old exr");
  {
    CommitGroup group;
    auto a = std::make_unique<PendingFile>(dir.path() / "a.exr");
    a->stream() << "new exr";
    group.add(std::move(a));
    EXPECT_EQ(contents(dir.path() / "a.exr"), "old exr");  // finished, synced, not yet renamed
    EXPECT_THROW(PendingFile(dir.path() / "missing" / "a.png"), std::runtime_error);
  }  // never committed
  EXPECT_EQ(contents(dir.path() / "a.exr"), "old exr");
  EXPECT_EQ(leftovers(dir.path()), 0);

  CommitGroup group;
  for (const char* name : {"a.png", "a.exr"}) {
    auto file = std::make_unique<PendingFile>(dir.path() / name);
    file->stream() << "new " << name;
    group.add(std::move(file));
  }
  group.commit();
  EXPECT_EQ(contents(dir.path() / "a.png"), "new a.png");
  EXPECT_EQ(contents(dir.path() / "a.exr"), "new a.exr");
  EXPECT_EQ(leftovers(dir.path()), 0);
}

}  // namespace io_atomic_file_test
}  // namespace penumbra
