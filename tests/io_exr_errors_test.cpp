// Failure paths of host/io/exr.h: missing, garbage, truncated and empty files, directories,
// unwritable paths and refused inputs all give a std::runtime_error that starts with the path, and
// a failed write leaves neither a temp file nor a changed target behind.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "host/io/exr.h"

namespace penumbra {
namespace io_exr_errors_test {

namespace fs = std::filesystem;

class ExrErrors : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           fmt::format("penumbra-io-ExrErrors.{}", ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ignored;
    fs::remove_all(dir_, ignored);
  }
  // The message of the std::runtime_error `f` throws; fails the test when it throws none.
  static std::string errorOf(const std::function<void()>& f) {
    try {
      f();
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    ADD_FAILURE() << "no std::runtime_error";
    return {};
  }
  static ::testing::AssertionResult startsWithPathAndSays(const std::string& message, const fs::path& path,
                                                          const std::string& reason) {
    if (message.rfind(path.string() + ": ", 0) == 0 && message.find(reason) != std::string::npos)
      return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "\"" << message << "\" should start with \"" << path.string()
                                         << ": \" and say \"" << reason << "\"";
  }
  void writeText(const fs::path& path, const std::string& text) const { std::ofstream(path) << text; }
  std::vector<std::string> filesInDir() const {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(dir_)) names.push_back(entry.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  }
  static Image smallImage() {
    Image image(3, 2);
    image.add("R", {0, 1, 2, 3, 4, 5});
    return image;
  }
  fs::path dir_;
};

TEST_F(ExrErrors, MissingFile) {
  const fs::path path = dir_ / "absent.exr";
  EXPECT_TRUE(startsWithPathAndSays(errorOf([&] { readExr(path); }), path, "no such file"));
  EXPECT_TRUE(startsWithPathAndSays(errorOf([&] { readExrInfo(path); }), path, "no such file"));
}

TEST_F(ExrErrors, GarbageEmptyAndDirectoryAreNotExr) {
  writeText(dir_ / "garbage.exr", "this is not an OpenEXR file, just some text");
  writeText(dir_ / "empty.exr", "");
  EXPECT_TRUE(startsWithPathAndSays(errorOf([&] { readExr(dir_ / "garbage.exr"); }), dir_ / "garbage.exr",
                                    "not an OpenEXR file"));
  EXPECT_TRUE(
      startsWithPathAndSays(errorOf([&] { readExr(dir_ / "empty.exr"); }), dir_ / "empty.exr", "not an OpenEXR file"));
  EXPECT_TRUE(startsWithPathAndSays(errorOf([&] { readExr(dir_); }), dir_, "is a directory"));
}

// Junk after the magic number is named as such, not taken for a deep image (whose flag random bytes often set); a
// version field that says deep but whose header does not read says why.
TEST_F(ExrErrors, JunkAfterTheMagicNumberIsNotADeepImage) {
  const auto withHead = [&](const char* name, std::initializer_list<unsigned char> head) {
    std::string bytes(head.begin(), head.end());
    for (int i = 0; i < 200; ++i) bytes += static_cast<char>((i * 97 + 13) & 0xff);
    writeText(dir_ / name, bytes);
    return dir_ / name;
  };
  const fs::path junk = withHead("junk.exr", {0x76, 0x2f, 0x31, 0x01, 0xf3, 0xb9, 0xb2, 0xab});
  EXPECT_TRUE(startsWithPathAndSays(errorOf([&] { readExr(junk); }), junk, "its version field is 0xabb2b9f3"));
  const fs::path deep = withHead("deep.exr", {0x76, 0x2f, 0x31, 0x01, 0x02, 0x08, 0x00, 0x00});
  const std::string message = errorOf([&] { readExrInfo(deep); });
  EXPECT_TRUE(startsWithPathAndSays(message, deep, "cannot read EXR header")) << message;
}

TEST_F(ExrErrors, TruncatedFileIsAnErrorNotACrash) {
  Image image(64, 64);  // incompressible values, so that pixel data fill most of the file
  std::vector<float> noise(64 * 64);
  for (size_t i = 0; i < noise.size(); ++i) noise[i] = std::sin(static_cast<float>(i) * 12.9898f) * 43758.5453f;
  image.add("R", noise);
  const fs::path path = dir_ / "truncated.exr";
  writeExr(path, image);
  for (const double keep : {0.9, 0.5, 0.1}) {
    const fs::path cut = dir_ / fmt::format("cut{}.exr", static_cast<int>(keep * 100));
    fs::copy_file(path, cut);
    fs::resize_file(cut, static_cast<uintmax_t>(static_cast<double>(fs::file_size(path)) * keep));
    // Depending on where the cut falls, the header or the pixel data are incomplete.
    EXPECT_TRUE(startsWithPathAndSays(errorOf([&] { readExr(cut); }), cut, "EXR")) << keep;
  }
}

TEST_F(ExrErrors, UnwritablePaths) {
  writeText(dir_ / "plain-file", "x");
  const fs::path underFile = dir_ / "plain-file" / "out.exr";  // ENOTDIR, even for root
  EXPECT_TRUE(startsWithPathAndSays(errorOf([&] { writeExr(underFile, smallImage()); }), underFile,
                                    "cannot create file: Not a directory"));
  const fs::path noDir = dir_ / "no" / "such" / "dir" / "out.exr";
  EXPECT_TRUE(startsWithPathAndSays(errorOf([&] { writeExr(noDir, smallImage()); }), noDir,
                                    "cannot create file: No such file or directory"));
  EXPECT_EQ(filesInDir(), std::vector<std::string>{"plain-file"});
}

TEST_F(ExrErrors, DirectoryTargetIsRefusedAndLeavesNoTempFile) {
  // The target is a directory: refused before anything is written (host/io/atomic_file.h), never renamed over.
  const fs::path target = dir_ / "taken.exr";
  fs::create_directory(target);
  EXPECT_TRUE(startsWithPathAndSays(errorOf([&] { writeExr(target, smallImage()); }), target, "is a directory"));
  EXPECT_EQ(filesInDir(), std::vector<std::string>{"taken.exr"});
  EXPECT_TRUE(fs::is_directory(target));
}

TEST_F(ExrErrors, RefusedInputLeavesExistingFileUntouched) {
  const fs::path path = dir_ / "keep.exr";
  writeExr(path, smallImage());
  const auto before = fs::file_size(path);

  Image reserved = smallImage();
  reserved.attributes()["compression"] = "none";
  EXPECT_TRUE(startsWithPathAndSays(errorOf([&] { writeExr(path, reserved); }), path,
                                    "attribute name 'compression' is reserved"));
  EXPECT_TRUE(startsWithPathAndSays(errorOf([&] { writeExr(path, smallImage(), {.halfChannels = {"Q"}}); }), path,
                                    "half channel 'Q' is not in the image"));
  EXPECT_TRUE(startsWithPathAndSays(errorOf([&] { writeExr(path, Image(2, 2)); }), path, "without channels"));
  EXPECT_TRUE(startsWithPathAndSays(errorOf([&] { writeExr(path, Image(0, 4)); }), path, "empty 0x4 image"));

  EXPECT_EQ(filesInDir(), std::vector<std::string>{"keep.exr"});
  EXPECT_EQ(fs::file_size(path), before);
  EXPECT_EQ(readExr(path).require("R").data, smallImage().require("R").data);
}

TEST_F(ExrErrors, OverwriteReplacesTheWholeFile) {
  const fs::path path = dir_ / "twice.exr";
  Image big(100, 100);
  big.add("R", std::vector<float>(100 * 100, 1.0f));
  writeExr(path, big);
  writeExr(path, smallImage());
  const Image read = readExr(path);
  EXPECT_EQ(read.width(), 3);
  EXPECT_EQ(filesInDir(), std::vector<std::string>{"twice.exr"});
}

}  // namespace io_exr_errors_test
}  // namespace penumbra
