// Tests of host/io/image.h: channel bookkeeping (sizes, unique names, lookup order), errors that
// name the image and the channel, and row flipping between bottom-up and top-down layouts.
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "host/io/image.h"

namespace penumbra {
namespace io_image_test {

// True when `what` occurs in the message of the exception `f` throws as E.
template <class E, class F>
::testing::AssertionResult throwsWith(F&& f, const std::string& what) {
  try {
    f();
  } catch (const E& e) {
    const std::string message = e.what();
    if (message.find(what) != std::string::npos) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "message \"" << message << "\" lacks \"" << what << "\"";
  }
  return ::testing::AssertionFailure() << "no exception";
}

TEST(Image, AddKeepsOrderAndFindsByName) {
  Image image(3, 2, "render.exr");
  image.add("R", std::vector<float>(6, 1.0f));
  image.add("visibility.Y", {0, 1, 2, 3, 4, 5});
  image.addFilled("A", 0.5f);
  EXPECT_EQ(image.width(), 3);
  EXPECT_EQ(image.height(), 2);
  EXPECT_EQ(image.pixelCount(), 6u);
  EXPECT_EQ(image.channelNames(), (std::vector<std::string>{"R", "visibility.Y", "A"}));
  ASSERT_NE(image.find("visibility.Y"), nullptr);
  EXPECT_EQ(image.find("visibility.Y")->data[4], 4.0f);
  EXPECT_EQ(image.find("A")->data, std::vector<float>(6, 0.5f));
  EXPECT_EQ(image.find("G"), nullptr);
  EXPECT_EQ(&image.require("R"), image.find("R"));
}

TEST(Image, RefusesWrongSizeDuplicateAndEmptyNames) {
  Image image(4, 3, "out.exr");
  EXPECT_TRUE(throwsWith<std::invalid_argument>([&] { image.add("R", std::vector<float>(11)); },
                                                "out.exr: channel 'R' has 11 values, expected 12"));
  image.add("R", std::vector<float>(12));
  EXPECT_TRUE(
      throwsWith<std::invalid_argument>([&] { image.add("R", std::vector<float>(12)); }, "channel 'R' added twice"));
  EXPECT_TRUE(
      throwsWith<std::invalid_argument>([&] { image.add("", std::vector<float>(12)); }, "channel name is empty"));
  EXPECT_TRUE(throwsWith<std::invalid_argument>([] { Image(-1, 2); }, "invalid image size -1x2"));
  EXPECT_EQ(image.channels().size(), 1u);
}

TEST(Image, RequireNamesImageChannelAndWhatExists) {
  Image image(1, 1, "shadow.exr");
  image.add("depth.Z", {1.0f});
  image.add("R", {0.0f});
  EXPECT_TRUE(throwsWith<std::runtime_error>([&] { image.require("visibility.Y"); },
                                             "shadow.exr: no channel 'visibility.Y' (channels: depth.Z, R)"));
  Image unnamed(1, 1);
  EXPECT_TRUE(throwsWith<std::runtime_error>([&] { unnamed.require("R"); }, "image: no channel 'R' (channels: none)"));
}

TEST(Image, AttributesAreFreeForm) {
  Image image(1, 1);
  image.attributes()["technique"] = "pcss";
  image.attributes()["device"] = "pthread-cpu";
  const Image& constImage = image;
  EXPECT_EQ(constImage.attributes().at("technique"), "pcss");
  EXPECT_EQ(constImage.attributes().size(), 2u);
}

TEST(ImageFlipRows, ReversesRowsForEvenOddAndSingleRowPlanes) {
  std::vector<float> even = {0, 1, 2, 10, 11, 12, 20, 21, 22, 30, 31, 32};  // 3x4
  flipRows(even, 3, 4);
  EXPECT_EQ(even, (std::vector<float>{30, 31, 32, 20, 21, 22, 10, 11, 12, 0, 1, 2}));
  std::vector<float> odd = {0, 1, 10, 11, 20, 21};  // 2x3: the middle row stays
  flipRows(odd, 2, 3);
  EXPECT_EQ(odd, (std::vector<float>{20, 21, 10, 11, 0, 1}));
  std::vector<float> single = {1, 2, 3};
  flipRows(single, 3, 1);
  EXPECT_EQ(single, (std::vector<float>{1, 2, 3}));
  std::vector<float> none;
  flipRows(none, 0, 0);
  EXPECT_TRUE(throwsWith<std::invalid_argument>([&] { flipRows(single, 2, 2); }, "3 values for a 2x2 plane"));
}

TEST(ImageFlipRows, ImageFlipsEveryChannelAndTwiceIsIdentity) {
  Image image(2, 3);
  image.add("R", {0, 1, 2, 3, 4, 5});
  image.add("G", {5, 4, 3, 2, 1, 0});
  image.flipRows();
  EXPECT_EQ(image.require("R").data, (std::vector<float>{4, 5, 2, 3, 0, 1}));
  EXPECT_EQ(image.require("G").data, (std::vector<float>{1, 0, 3, 2, 5, 4}));
  image.flipRows();
  EXPECT_EQ(image.require("R").data, (std::vector<float>{0, 1, 2, 3, 4, 5}));
}

}  // namespace io_image_test
}  // namespace penumbra
