// Tests of host/io/exr.h: round trips of many channels at odd sizes (1x1, 3x7, 257x129), attributes,
// each lossless compression and pixel types read back from the header, half precision, NaN/Inf, data windows
// not at the origin (a fixture written by the OpenEXR C++ API), and errors that name the path.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "host/io/exr.h"
#include "tests/support/compare.h"

namespace penumbra {
namespace io_exr_test {

namespace fs = std::filesystem;

// Rounding to half keeps 11 significant bits: relative error at most 2^-11 for normal halves.
constexpr double kHalfRelative = 1.0 / 2048.0;
const test::Tolerance kExact{0.0, 0.0, true};  // float channels are stored bit for bit

// A fresh scratch directory per test, removed afterwards.
class ExrTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = fmt::format("penumbra-io-{}.{}", info->test_suite_name(), info->name());
    for (char& c : name)
      if (c == '/') c = '_';
    dir_ = fs::temp_directory_path() / name;
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ignored;
    fs::remove_all(dir_, ignored);
  }
  fs::path dir_;
};

// Deterministic values of both signs and many magnitudes, distinct per channel.
std::vector<float> pattern(int width, int height, int seed) {
  std::vector<float> values(static_cast<size_t>(width) * height);
  uint32_t state = 2654435761u * static_cast<uint32_t>(seed + 1);
  for (float& v : values) {
    state = state * 1664525u + 1013904223u;
    v = (static_cast<float>(state >> 8) / 16777216.0f - 0.5f) * std::ldexp(1.0f, seed % 7 - 2);
  }
  return values;
}

const std::vector<std::string> kChannelNames = {"R",   "G",   "B",   "A",   "visibility.Y", "P.X",    "P.Y",
                                                "P.Z", "N.X", "N.Y", "N.Z", "depth.Z",      "layer.Y"};

Image patternImage(int width, int height) {
  Image image(width, height);
  for (size_t i = 0; i < kChannelNames.size(); ++i)
    image.add(kChannelNames[i], pattern(width, height, static_cast<int>(i)));
  image.attributes() = {{"technique", "pcss"},
                        {"parameters", "{\"blocker\": 16, \"filter\": 32}"},
                        {"device", "Portable Computing Language / cpu"},
                        {"empty", ""}};
  return image;
}

struct Size {
  int width, height;
};

class ExrRoundTrip : public ExrTest, public ::testing::WithParamInterface<Size> {};

TEST_P(ExrRoundTrip, EveryChannelAndAttributeSurvivesAsZipFloat) {
  const auto [width, height] = GetParam();
  const Image written = patternImage(width, height);
  const fs::path path = dir_ / "round trip.exr";
  writeExr(path, written);

  const Image read = readExr(path);
  EXPECT_EQ(read.source(), path.string());
  ASSERT_EQ(read.width(), width);
  ASSERT_EQ(read.height(), height);
  ASSERT_EQ(read.channels().size(), written.channels().size());
  for (const ImageChannel& channel : written.channels())
    EXPECT_TRUE((
        test::allNear<float, float>(read.require(channel.name).data, channel.data, kExact, static_cast<size_t>(width))))
        << channel.name;
  for (const auto& [name, value] : written.attributes()) {
    ASSERT_TRUE(read.attributes().count(name)) << name;
    EXPECT_EQ(read.attributes().at(name), value) << name;
  }

  const ExrInfo info = readExrInfo(path);
  EXPECT_EQ(info.compression, "zip");
  EXPECT_FALSE(info.tiled);
  EXPECT_EQ(info.dataWindow.minX, 0);
  EXPECT_EQ(info.dataWindow.minY, 0);
  EXPECT_EQ(info.dataWindow.width(), width);
  EXPECT_EQ(info.dataWindow.height(), height);
  ASSERT_EQ(info.channels.size(), kChannelNames.size());
  for (const ExrChannelInfo& channel : info.channels)
    EXPECT_EQ(channel.type, ExrPixelType::Float) << channel.name << " is " << exrPixelTypeName(channel.type);
}

INSTANTIATE_TEST_SUITE_P(ExrOddSizes, ExrRoundTrip, ::testing::Values(Size{1, 1}, Size{3, 7}, Size{257, 129}),
                         [](const auto& param) { return fmt::format("{}x{}", param.param.width, param.param.height); });

// Numbers as EXR doubles and matrices as m44f survive exactly; a name in two maps, or a reserved one, is refused.
// Every lossless compression stores the same bits (float and half channels, NaN included) and says so in the header.
class ExrCompressions : public ExrTest, public ::testing::WithParamInterface<ExrCompression> {};

TEST_P(ExrCompressions, StoreTheSameBitsAndNameThemselves) {
  Image written = patternImage(37, 19);
  written.find("visibility.Y")->data[5] = std::numeric_limits<float>::quiet_NaN();
  ExrOptions options;
  options.compression = GetParam();
  options.halfChannels = {"R", "G", "B"};
  const fs::path path = dir_ / "compressed.exr";
  writeExr(path, written, options);

  const ExrInfo info = readExrInfo(path);
  EXPECT_EQ(info.compression, exrCompressionName(GetParam()));
  const Image read = readExr(path);
  for (const ImageChannel& channel : written.channels()) {
    const std::vector<float>& got = read.require(channel.name).data;
    if (options.halfChannels.count(channel.name)) {
      // Half channels: the rounding is the format's, not the compression's (ZIP's read-back as reference).
      ExrOptions zip = options;
      zip.compression = ExrCompression::Zip;
      writeExr(dir_ / "zip.exr", written, zip);
      EXPECT_TRUE((test::allNear<float, float>(got, readExr(dir_ / "zip.exr").require(channel.name).data, kExact)))
          << channel.name;
    } else {
      EXPECT_TRUE((test::allNear<float, float>(got, channel.data, kExact))) << channel.name;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Lossless, ExrCompressions,
                         ::testing::Values(ExrCompression::None, ExrCompression::Rle, ExrCompression::Zips,
                                           ExrCompression::Zip, ExrCompression::Piz),
                         [](const auto& param) { return std::string(exrCompressionName(param.param)); });

TEST(ExrCompressionNames, RoundTripAndRefuseLossyOrUnknownNames) {
  for (const char* name : {"none", "rle", "zips", "zip", "piz"})
    EXPECT_STREQ(exrCompressionName(parseExrCompression(name)), name);
  for (const char* name : {"dwaa", "b44", "pxr24", "ZIP", "", "zip "}) {
    try {
      parseExrCompression(name);
      ADD_FAILURE() << "'" << name << "' was accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("use none, rle, zips, zip or piz"), std::string::npos) << e.what();
    }
  }
}

TEST_F(ExrTest, NumbersAndMatricesSurviveAsTypedAttributes) {
  Image image = patternImage(3, 2);
  image.numbers() = {{"penumbra:rays", 123456789012.0}, {"penumbra:stderr-mean", 0.1234567890123}};
  Matrix44 m;
  for (size_t i = 0; i < m.size(); ++i) m[i] = 0.5f * static_cast<float>(i) - 3.0f;
  image.matrices()["worldToCamera"] = m;
  writeExr(dir_ / "typed.exr", image);
  const Image read = readExr(dir_ / "typed.exr");
  EXPECT_EQ(read.numbers(), image.numbers());  // nothing of the header's own float fields (pixelAspectRatio)
  EXPECT_EQ(read.matrices(), image.matrices());
  EXPECT_EQ(read.attributes().count("penumbra:rays"), 0u);

  image.attributes()["worldToCamera"] = "text";
  EXPECT_THROW(writeExr(dir_ / "twice.exr", image), std::runtime_error);
  image.attributes().erase("worldToCamera");
  image.numbers()["pixelAspectRatio"] = 2.0;
  EXPECT_THROW(writeExr(dir_ / "reserved.exr", image), std::runtime_error);
}

TEST_F(ExrTest, HalfChannelsAreHalfAndWithinHalfPrecision) {
  Image image(5, 3);
  std::vector<float> colour(15);
  for (size_t i = 0; i < colour.size(); ++i) colour[i] = 0.001f * std::pow(3.1f, static_cast<float>(i) * 0.9f);
  image.add("R", colour);
  image.add("depth.Z", colour);
  std::vector<float> overflow(15, 1.0e5f);  // beyond half's 65504
  image.add("G", overflow);
  writeExr(dir_ / "half.exr", image, {.halfChannels = {"R", "G"}});

  const ExrInfo info = readExrInfo(dir_ / "half.exr");
  for (const ExrChannelInfo& channel : info.channels)
    EXPECT_EQ(channel.type, channel.name == "depth.Z" ? ExrPixelType::Float : ExrPixelType::Half) << channel.name;
  const Image read = readExr(dir_ / "half.exr");
  EXPECT_TRUE((test::allNear<float, float>(read.require("R").data, colour, {0.0, kHalfRelative})));
  EXPECT_TRUE((test::allNear<float, float>(read.require("depth.Z").data, colour, kExact)));
  EXPECT_TRUE(std::isinf(read.require("G").data[0]));
}

TEST_F(ExrTest, NanInfSignedZeroAndDenormalsSurviveInFloatChannels) {
  constexpr float kInf = std::numeric_limits<float>::infinity();
  const std::vector<float> special = {std::numeric_limits<float>::quiet_NaN(),
                                      kInf,
                                      -kInf,
                                      -0.0f,
                                      std::numeric_limits<float>::denorm_min(),
                                      std::numeric_limits<float>::max(),
                                      -std::numeric_limits<float>::max(),
                                      1.0f};
  Image written(4, 2);
  written.add("visibility.Y", special);
  writeExr(dir_ / "special.exr", written);
  const Image image = readExr(dir_ / "special.exr");
  const std::vector<float>& read = image.require("visibility.Y").data;
  ASSERT_EQ(read.size(), special.size());
  EXPECT_TRUE(std::isnan(read[0]));
  EXPECT_TRUE((test::allNear<float, float>(read, special, kExact)));
  EXPECT_TRUE(std::signbit(read[3]));
  EXPECT_EQ(read[4], std::numeric_limits<float>::denorm_min());
}

// tests/data/io/data_window.exr: written by make_data_window_exr.cpp beside it (OpenEXR C++ API);
// data window (5, 3) - (11, 7) in a 16x12 display window, PIZ, channels of all three pixel types.
TEST_F(ExrTest, DataWindowAwayFromOriginReadsEveryPixelTypeAsFloat) {
  const fs::path path = fs::path(PENUMBRA_TEST_DATA_DIR) / "io" / "data_window.exr";
  const ExrInfo info = readExrInfo(path);
  EXPECT_EQ(info.compression, "piz");
  EXPECT_EQ(info.dataWindow.minX, 5);
  EXPECT_EQ(info.dataWindow.minY, 3);
  EXPECT_EQ(info.dataWindow.maxX, 11);
  EXPECT_EQ(info.dataWindow.maxY, 7);
  EXPECT_EQ(info.displayWindow.width(), 16);
  EXPECT_EQ(info.displayWindow.height(), 12);

  const Image image = readExr(path);
  ASSERT_EQ(image.width(), 7);
  ASSERT_EQ(image.height(), 5);
  EXPECT_EQ(image.channelNames(), (std::vector<std::string>{"H", "I", "Y"}));  // EXR sorts by name
  for (int row = 0; row < 5; ++row)
    for (int col = 0; col < 7; ++col) {
      const int x = 5 + col, y = 3 + row;
      const size_t i = static_cast<size_t>(row) * 7 + col;
      EXPECT_EQ(image.require("Y").data[i], static_cast<float>(x + 100 * y)) << col << ", " << row;
      EXPECT_EQ(image.require("H").data[i], 0.25f * static_cast<float>(x - y)) << col << ", " << row;
      EXPECT_EQ(image.require("I").data[i], static_cast<float>(x * y)) << col << ", " << row;
    }
  EXPECT_EQ(image.attributes().at("comment"), "data window fixture");
  EXPECT_EQ(image.attributes().count("exposure"), 0u);  // a float attribute, not a string
}

}  // namespace io_exr_test
}  // namespace penumbra
