// Tests of host/io/png.h: the sRGB transfer function against a double-precision
// reference and known codes, viridis against matplotlib's table, and PNG files decoded back with
// stb_image (size, channel count, top row first, exposure, alpha, NaN -> magenta, false colour).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#define STB_IMAGE_STATIC  // private copy: cannot clash with another stb linked into the tests
#define STB_IMAGE_IMPLEMENTATION
#include <stb/stb_image.h>

#include "host/io/image_rows.h"
#include "host/io/png.h"

namespace penumbra {
namespace io_png_test {

namespace fs = std::filesystem;

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
// srgbEncode runs in float: a few ulps of pow() on values up to 1.
constexpr double kSrgbTolerance = 1e-6;
// The 33-knot viridis table vs matplotlib's 256 entries (worst near the blue minimum, entry ~244).
constexpr int kViridisTolerance = 2;

double srgbReference(double linear) {  // IEC 61966-2-1, written out independently in double
  return linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
}

TEST(PngColour, SrgbEncodeMatchesDoubleReference) {
  for (int i = 0; i <= 4096; ++i) {
    const double linear = i / 4096.0;
    EXPECT_NEAR(srgbEncode(static_cast<float>(linear)), srgbReference(linear), kSrgbTolerance) << linear;
  }
}

TEST(PngColour, SrgbKnownCodes) {
  EXPECT_EQ(srgbByte(0.0f), 0);
  EXPECT_EQ(srgbByte(1.0f), 255);
  EXPECT_EQ(srgbByte(0.5f), 188);  // a 2.2 gamma would give 186
  EXPECT_EQ(srgbByte(0.0031308f), 10);
  EXPECT_EQ(srgbByte(0.001f), 3);  // linear toe: 12.92 * 0.001; a 2.2 gamma would give 11
  // Both pieces meet at the boundary.
  EXPECT_NEAR(srgbEncode(std::nextafter(0.0031308f, 0.0f)), srgbEncode(std::nextafter(0.0031308f, 1.0f)), 1e-6);
  EXPECT_EQ(srgbByte(-1.0f), 0);
  EXPECT_EQ(srgbByte(7.0f), 255);
  EXPECT_EQ(srgbByte(std::numeric_limits<float>::infinity()), 255);
  EXPECT_EQ(unormByte(0.5f), 128);
  EXPECT_EQ(unormByte(kNaN), 0);
}

TEST(PngColour, ViridisEndpointsAndTableEntries) {
  EXPECT_EQ(viridis(0.0f), (Rgb8{68, 1, 84}));
  EXPECT_EQ(viridis(1.0f), (Rgb8{253, 231, 37}));
  EXPECT_EQ(viridis(-3.0f), viridis(0.0f));
  EXPECT_EQ(viridis(3.0f), viridis(1.0f));
  EXPECT_EQ(viridis(kNaN), kNanColour);
  struct Entry {
    int index;
    double r, g, b;
  };
  // Entries of matplotlib's _viridis_data that are not knots of our table.
  for (const Entry& e : {Entry{4, 0.272594, 0.025563, 0.353093}, Entry{100, 0.166617, 0.463708, 0.558119},
                         Entry{180, 0.274149, 0.751988, 0.436601}, Entry{244, 0.886271, 0.892374, 0.095374},
                         Entry{250, 0.945636, 0.899815, 0.112838}}) {
    const Rgb8 c = viridis(static_cast<float>(e.index) / 255.0f);
    EXPECT_NEAR(c[0], e.r * 255.0, kViridisTolerance) << e.index;
    EXPECT_NEAR(c[1], e.g * 255.0, kViridisTolerance) << e.index;
    EXPECT_NEAR(c[2], e.b * 255.0, kViridisTolerance) << e.index;
  }
}

TEST(PngColour, FalseColourMapsRangeAndClamps) {
  EXPECT_EQ(falseColour(-2.0f, -2.0f, 6.0f), viridis(0.0f));
  EXPECT_EQ(falseColour(6.0f, -2.0f, 6.0f), viridis(1.0f));
  EXPECT_EQ(falseColour(2.0f, -2.0f, 6.0f), viridis(0.5f));
  EXPECT_EQ(falseColour(-std::numeric_limits<float>::infinity(), 0.0f, 1.0f), viridis(0.0f));
  EXPECT_EQ(falseColour(std::numeric_limits<float>::infinity(), 0.0f, 1.0f), viridis(1.0f));
  EXPECT_EQ(falseColour(kNaN, 0.0f, 1.0f), kNanColour);
  EXPECT_EQ(falseColour(0.0f, 0.0f, 0.0f), viridis(0.0f));  // constant image: still renders
  EXPECT_EQ(falseColour(1e-3f, 0.0f, 0.0f), viridis(1.0f));
}

struct Decoded {
  int width = 0, height = 0, components = 0;
  std::vector<std::uint8_t> pixels;
  const std::uint8_t* at(int x, int y) const { return &pixels[(static_cast<size_t>(y) * width + x) * components]; }
  Rgb8 rgb(int x, int y) const { return {at(x, y)[0], at(x, y)[1], at(x, y)[2]}; }
};

class PngTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           fmt::format("penumbra-io-{}.{}", ::testing::UnitTest::GetInstance()->current_test_info()->test_suite_name(),
                       ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ignored;
    fs::remove_all(dir_, ignored);
  }
  static Decoded decode(const fs::path& path) {
    Decoded d;
    std::uint8_t* data = stbi_load(path.c_str(), &d.width, &d.height, &d.components, 0);
    if (data == nullptr) {
      ADD_FAILURE() << path << ": " << stbi_failure_reason();
      return d;
    }
    d.pixels.assign(data, data + static_cast<size_t>(d.width) * d.height * d.components);
    stbi_image_free(data);
    return d;
  }
  // An image whose R = G = B = `grey`, width = grey.size(), one row.
  static Image greyRow(const std::vector<float>& grey) {
    Image image(static_cast<int>(grey.size()), 1);
    for (const char* name : {"R", "G", "B"}) image.add(name, grey);
    return image;
  }
  fs::path dir_;
};

using PngPreview = PngTest;
using PngFalseColour = PngTest;

TEST_F(PngPreview, DecodesToRightSizeTopRowFirst) {
  Image image(3, 7);
  std::vector<float> red(21, 0.0f);
  red[0] = red[1] = red[2] = 1.0f;  // row 0 = top row of the picture
  image.add("R", red);
  image.addFilled("G", 0.0f);
  image.addFilled("B", 0.0f);
  writePngPreview(dir_ / "rgb.png", image);
  const Decoded d = decode(dir_ / "rgb.png");
  EXPECT_EQ(d.width, 3);
  EXPECT_EQ(d.height, 7);
  EXPECT_EQ(d.components, 3);
  EXPECT_EQ(d.rgb(1, 0), (Rgb8{255, 0, 0}));
  EXPECT_EQ(d.rgb(1, 6), (Rgb8{0, 0, 0}));
}

TEST_F(PngPreview, SrgbCodesOfKnownValuesAndExposure) {
  writePngPreview(dir_ / "known.png", greyRow({0.0f, 1.0f, 0.5f, 0.0031308f}));
  const Decoded d = decode(dir_ / "known.png");
  ASSERT_EQ(d.width, 4);
  EXPECT_EQ(d.rgb(0, 0), (Rgb8{0, 0, 0}));
  EXPECT_EQ(d.rgb(1, 0), (Rgb8{255, 255, 255}));
  EXPECT_EQ(d.rgb(2, 0), (Rgb8{188, 188, 188}));
  EXPECT_EQ(d.rgb(3, 0), (Rgb8{10, 10, 10}));
  PngOptions plusOneStop;
  plusOneStop.exposure = 1.0f;  // 0.25 * 2 = 0.5
  writePngPreview(dir_ / "exposed.png", greyRow({0.25f}), plusOneStop);
  EXPECT_EQ(decode(dir_ / "exposed.png").rgb(0, 0), (Rgb8{188, 188, 188}));
}

TEST_F(PngPreview, NanIsMagentaInEveryChannelAndWithAlpha) {
  Image image(4, 1);
  image.add("R", {kNaN, 0.5f, 0.5f, 0.5f});
  image.add("G", {0.5f, kNaN, 0.5f, 0.5f});
  image.add("B", {0.5f, 0.5f, 0.5f, 0.5f});
  image.add("A", {1.0f, 1.0f, kNaN, 1.0f});
  writePngPreview(dir_ / "nan.png", image);
  const Decoded d = decode(dir_ / "nan.png");
  ASSERT_EQ(d.components, 4);
  for (int x = 0; x < 3; ++x) {
    EXPECT_EQ(d.rgb(x, 0), kNanColour) << x;
    EXPECT_EQ(d.at(x, 0)[3], 255) << x;
  }
  EXPECT_EQ(d.rgb(3, 0), (Rgb8{188, 188, 188}));
}

TEST_F(PngPreview, AlphaIsUnpremultiplied) {
  Image image = greyRow({0.25f, 0.0f});
  image.add("A", {0.5f, 0.0f});
  writePngPreview(dir_ / "alpha.png", image);
  const Decoded d = decode(dir_ / "alpha.png");
  ASSERT_EQ(d.components, 4);
  EXPECT_EQ(d.rgb(0, 0), (Rgb8{188, 188, 188}));  // 0.25 / 0.5 = 0.5 straight
  EXPECT_EQ(d.at(0, 0)[3], 128);
  EXPECT_EQ(d.at(1, 0)[3], 0);
}

TEST_F(PngPreview, GreyChannelAndErrorsNameThePath) {
  Image image(2, 1, "shadow.exr");
  image.add("visibility.Y", {1.0f, 0.5f});
  writePngPreview(dir_ / "vis.png", image, {.greyChannel = "visibility.Y"});
  const Decoded d = decode(dir_ / "vis.png");
  EXPECT_EQ(d.components, 3);
  EXPECT_EQ(d.rgb(1, 0), (Rgb8{188, 188, 188}));

  const fs::path out = dir_ / "rgb.png";
  try {
    writePngPreview(out, image);
    ADD_FAILURE() << "no error for a missing R";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()),
              out.string() + ": cannot preview: shadow.exr: no channel 'R' (channels: visibility.Y)");
  }
  const fs::path bad = dir_ / "not-a-dir" / "x.png";
  std::ofstream(dir_ / "not-a-dir") << "x";
  EXPECT_THROW(writePngPreview(bad, greyRow({0.5f})), std::runtime_error);
  EXPECT_FALSE(fs::exists(dir_ / "rgb.png"));
}

// The preview read band by band from deferred channels (three rows a band, 31 rows: a last band of one) decodes to
// the same bytes as the whole image's, in colour and grey; a reader that fails mid-way leaves no file.
TEST_F(PngPreview, BandsFromDeferredChannelsEqualTheWholeImage) {
  Image image(29, 31);
  for (const char* name : {"R", "G", "B", "A", "visibility.Y"}) {
    std::vector<float> values(image.pixelCount());
    for (size_t i = 0; i < values.size(); ++i) values[i] = std::fmod(0.37f * static_cast<float>(i) + *name, 1.1f);
    values[5] = kNaN;
    image.add(name, values);
  }
  const Image header(image.width(), image.height());
  std::vector<DeferredChannel> deferred;
  for (const std::string& name : image.channelNames())
    deferred.push_back({name, [&image, name](int first, int count, std::span<float> out) {
                          ImageRows(image).read(name, first, count, out);
                        }});
  PngOptions bands;
  bands.bandBytes = 29 * 4 * 4 * 3;
  for (const std::string grey : {"", "visibility.Y"}) {
    bands.greyChannel = grey;
    writePngPreview(dir_ / "whole.png", image, {.greyChannel = grey});
    writePngPreview(dir_ / "bands.png", ImageRows(header, deferred), bands);
    const Decoded whole = decode(dir_ / "whole.png"), banded = decode(dir_ / "bands.png");
    EXPECT_EQ(whole.components, grey.empty() ? 4 : 3);
    EXPECT_EQ(banded.width, 29);
    EXPECT_EQ(banded.height, 31);
    EXPECT_EQ(whole.pixels, banded.pixels) << grey;
  }
  deferred[1].read = [](int first, int, std::span<float>) {
    if (first > 0) throw std::runtime_error("device lost");
  };
  bands.greyChannel.clear();
  fs::remove(dir_ / "bands.png");
  EXPECT_THROW(writePngPreview(dir_ / "bands.png", ImageRows(header, deferred), bands), std::runtime_error);
  EXPECT_FALSE(fs::exists(dir_ / "bands.png"));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1);  // whole.png, no temporary
}

TEST_F(PngFalseColour, EndpointsNanAndClamping) {
  const std::vector<float> values = {-1.0f, 3.0f, kNaN, -50.0f, 50.0f, 1.0f};  // 3x2, range [-1, 3]
  writePngFalseColour(dir_ / "error.png", 3, 2, values, -1.0f, 3.0f);
  const Decoded d = decode(dir_ / "error.png");
  ASSERT_EQ(d.width, 3);
  ASSERT_EQ(d.height, 2);
  ASSERT_EQ(d.components, 3);
  EXPECT_EQ(d.rgb(0, 0), (Rgb8{68, 1, 84}));
  EXPECT_EQ(d.rgb(1, 0), (Rgb8{253, 231, 37}));
  EXPECT_EQ(d.rgb(2, 0), kNanColour);
  EXPECT_EQ(d.rgb(0, 1), (Rgb8{68, 1, 84}));
  EXPECT_EQ(d.rgb(1, 1), (Rgb8{253, 231, 37}));
  EXPECT_EQ(d.rgb(2, 1), viridis(0.5f));
}

TEST_F(PngFalseColour, RefusesBadSizesAndRanges) {
  const std::vector<float> values(6, 0.0f);
  EXPECT_THROW(writePngFalseColour(dir_ / "a.png", 4, 2, values, 0.0f, 1.0f), std::invalid_argument);
  EXPECT_THROW(writePngFalseColour(dir_ / "a.png", 3, 2, values, 1.0f, 0.0f), std::invalid_argument);
  EXPECT_THROW(writePngFalseColour(dir_ / "a.png", 3, 2, values, kNaN, 1.0f), std::invalid_argument);
  EXPECT_FALSE(fs::exists(dir_ / "a.png"));
}

}  // namespace io_png_test
}  // namespace penumbra
