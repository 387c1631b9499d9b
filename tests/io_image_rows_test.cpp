// ImageRows and the banded EXR writer: a view's names, reads and refusals; the EXR written band by band from deferred
// channels equals, bit for bit, the file written from the whole Image, for sizes that are no multiple of a band, with
// NaN, infinities and a half channel; a failing read leaves no file. (The banded PNG: io_png_test.cpp.)
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "host/io/exr.h"
#include "host/io/image_rows.h"
#include "tests/support/temp_dir.h"

namespace penumbra {
namespace io_image_rows_test {

namespace fs = std::filesystem;

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// A width x height image of `channels` channels of random values with a NaN, +-Inf and huge values among them.
Image randomImage(int width, int height, const std::vector<std::string>& channels, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> value(-0.2f, 1.2f);
  Image image(width, height, "random.exr");
  for (const std::string& name : channels) {
    std::vector<float> data(image.pixelCount());
    for (float& v : data) v = value(rng);
    data[0] = kNaN, data[data.size() / 2] = kInf, data.back() = -kInf;
    data[data.size() / 3] = 3e38f;
    image.add(name, std::move(data));
  }
  image.attributes()["penumbra:technique"] = "sm";
  image.numbers()["penumbra:number"] = 2.5;
  return image;
}

// `image` without its channels (the header a deferred frame keeps) and a reader per channel that records the bands
// it was asked for.
struct Deferred {
  Image header;
  std::vector<DeferredChannel> channels;
  std::vector<std::pair<int, int>> bands;  // (first, count) of every read
};

Deferred deferAll(const Image& image) {
  Deferred out{Image(image.width(), image.height(), image.source()), {}, {}};
  out.header.attributes() = image.attributes();
  out.header.numbers() = image.numbers();
  out.header.matrices() = image.matrices();
  for (const ImageChannel& channel : image.channels())
    out.channels.push_back(
        {channel.name, [&image, &out, name = channel.name](int first, int count, std::span<float> values) {
           out.bands.emplace_back(first, count);
           ImageRows(image).read(name, first, count, values);
         }});
  return out;
}

// Bit for bit, NaN included.
void expectSameChannels(const Image& a, const Image& b) {
  ASSERT_EQ(a.channelNames(), b.channelNames());
  for (const ImageChannel& channel : a.channels()) {
    const std::vector<float>& other = b.require(channel.name).data;
    ASSERT_EQ(channel.data.size(), other.size());
    EXPECT_EQ(std::memcmp(channel.data.data(), other.data(), other.size() * sizeof(float)), 0) << channel.name;
  }
}

TEST(ImageRows, NamesReadsAndRefusals) {
  Image image(3, 4, "frame.exr");
  image.add("R", {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11});
  const std::vector<DeferredChannel> deferred = {{"depth.Z", [](int first, int count, std::span<float> out) {
                                                    for (size_t i = 0; i < out.size(); ++i)
                                                      out[i] = static_cast<float>(first * 100 + count * 10) + i;
                                                  }}};
  const ImageRows rows(image, deferred);
  EXPECT_EQ(rows.channelNames(), (std::vector<std::string>{"R", "depth.Z"}));
  EXPECT_TRUE(rows.has("depth.Z"));
  EXPECT_FALSE(rows.has("G"));
  std::vector<float> band(6);
  rows.read("R", 2, 2, band);
  EXPECT_EQ(band, (std::vector<float>{6, 7, 8, 9, 10, 11}));
  rows.read("depth.Z", 1, 2, band);
  EXPECT_EQ(band, (std::vector<float>{120, 121, 122, 123, 124, 125}));

  // A held channel's rows in place (what writeExr hands OpenEXR without a copy); none for a deferred one.
  const std::span<const float> held = rows.stored("R", 1, 2);
  EXPECT_EQ(held.data(), image.find("R")->data.data() + 3);
  EXPECT_EQ(std::vector<float>(held.begin(), held.end()), (std::vector<float>{3, 4, 5, 6, 7, 8}));
  EXPECT_TRUE(rows.stored("depth.Z", 0, 2).empty());
  EXPECT_TRUE(rows.stored("G", 0, 2).empty());
  EXPECT_THROW(rows.stored("R", 3, 2), std::out_of_range);

  std::vector<float> none;
  rows.read("R", 4, 0, none);  // an empty band at the end is fine
  EXPECT_THROW(rows.read("R", 3, 2, band), std::out_of_range);
  EXPECT_THROW(rows.read("R", -1, 2, band), std::out_of_range);
  EXPECT_THROW(rows.read("R", 0, 1, band), std::out_of_range);  // 6 values for one row of 3
  try {
    rows.read("G", 0, 2, band);
    ADD_FAILURE() << "no error for a missing channel";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "frame.exr: no channel 'G' (channels: R, depth.Z)");
  }
  const RowReader any = [](int, int, std::span<float>) {};
  const std::vector<DeferredChannel> twiceR = {{"R", any}};
  EXPECT_THROW(ImageRows(image, twiceR), std::invalid_argument);
  const std::vector<DeferredChannel> twice = {{"A", any}, {"A", any}};
  EXPECT_THROW(ImageRows(image, twice), std::invalid_argument);
  const std::vector<DeferredChannel> unnamed = {{"", any}};
  EXPECT_THROW(ImageRows(image, unnamed), std::invalid_argument);
}

TEST(ImageRows, BandRowsAreWholeMultiplesWithinTheBudget) {
  EXPECT_EQ(bandRows(8192, 14, size_t{32} << 20, 16), 64);  // 14 channels of 8192 floats: 458,752 bytes a row
  EXPECT_EQ(bandRows(8192, 14, 1, 16), 16);                 // never below one block
  EXPECT_EQ(bandRows(1, 1, size_t{1} << 40, 1), 1 << 20);   // capped
  EXPECT_EQ(bandRows(0, 0, 100, 4), 24);                    // degenerate sizes count as 1
  EXPECT_EQ(bandRows(100, 4, 1600 * 5 + 1, 1), 5);
}

TEST(ImageRowsFiles, ExrWrittenInBandsEqualsTheWholeImage) {
  const test::TempDir dir("penumbra_rows");
  const fs::path& folder = dir.path();
  for (const auto& [width, height] : {std::pair{37, 53}, {1, 1}, {5, 16}, {64, 17}}) {
    SCOPED_TRACE(fmt::format("{}x{}", width, height));
    const Image image = randomImage(width, height, {"R", "G", "P.X", "depth.Z"}, 7u + width);
    ExrOptions options;
    options.halfChannels = {"G"};
    writeExr(folder / "whole.exr", image, options);
    Deferred deferred = deferAll(image);
    options.bandBytes = 1;  // one 16-row block a band
    writeExr(folder / "bands.exr", ImageRows(deferred.header, deferred.channels), options);
    writeExr(folder / "held-bands.exr", image, options);  // the image's own rows, a band at a time

    const Image whole = readExr(folder / "whole.exr"), bands = readExr(folder / "bands.exr");
    expectSameChannels(whole, bands);
    expectSameChannels(whole, readExr(folder / "held-bands.exr"));
    for (const char* name : {"R", "P.X", "depth.Z"})  // bit for bit (NaN included)
      EXPECT_EQ(
          std::memcmp(whole.find(name)->data.data(), image.find(name)->data.data(), image.pixelCount() * sizeof(float)),
          0)
          << name;
    EXPECT_EQ(bands.attributes().at("penumbra:technique"), "sm");
    EXPECT_EQ(bands.numbers().at("penumbra:number"), 2.5);
    // Every row read once, in order, in bands of 16 rows (the last one shorter).
    int next = 0;
    for (size_t i = 0; i < deferred.bands.size(); i += 4) {
      EXPECT_EQ(deferred.bands[i].first, next);
      EXPECT_EQ(deferred.bands[i].second, std::min(16, height - next));
      next += deferred.bands[i].second;
    }
    EXPECT_EQ(next, height);
    EXPECT_EQ(deferred.bands.size(), 4u * static_cast<size_t>((height + 15) / 16));
  }
}

TEST(ImageRowsFiles, AFailingReaderLeavesNoFile) {
  const test::TempDir dir("penumbra_rows");
  const fs::path& folder = dir.path();
  const Image image = randomImage(8, 40, {"R", "G", "B"}, 5u);
  Deferred deferred = deferAll(image);
  deferred.channels[1].read = [](int first, int, std::span<float>) {
    if (first > 0) throw std::runtime_error("device lost");
  };
  ExrOptions exr;
  exr.bandBytes = 1;
  EXPECT_THROW(writeExr(folder / "x.exr", ImageRows(deferred.header, deferred.channels), exr), std::runtime_error);
  EXPECT_TRUE(fs::is_empty(folder));  // neither the file nor its temporary
}

}  // namespace io_image_rows_test
}  // namespace penumbra
