#include "core/image/image.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "core/util/error.h"

namespace loom {
namespace {

std::filesystem::path TempPath(const std::string& name) {
  return std::filesystem::path(::testing::TempDir()) / ("loom_image_test_" + name);
}

Image Gradient(int channels) {
  Image image(7, 5, channels);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      for (int c = 0; c < channels; ++c) image.at(x, y, c) = 0.03f * x + 0.11f * y + 0.2f * c;
  return image;
}

TEST(Image, ExrRoundTripKeepsLinearValuesToHalfPrecision) {
  Image image = Gradient(4);
  image.at(0, 0, 0) = 37.5f;  // HDR values survive
  const auto path = TempPath("round_trip.exr");
  WriteImage(image, path);
  const Image read = ReadImage(path);
  ASSERT_EQ(read.width, image.width);
  ASSERT_EQ(read.height, image.height);
  ASSERT_EQ(read.channels, 4);
  for (size_t i = 0; i < image.pixels.size(); ++i) {
    EXPECT_NEAR(read.pixels[i], image.pixels[i], std::abs(image.pixels[i]) * 1e-3f + 1e-4f) << i;
  }
}

TEST(Image, ExrClampsValuesBeyondHalfRangeInsteadOfStoringInf) {
  Image image = Gradient(3);
  image.at(1, 1, 0) = 1e6f;
  image.at(2, 1, 1) = -1e6f;
  image.at(3, 1, 2) = std::nanf("");
  const auto path = TempPath("beyond_half.exr");
  WriteImage(image, path);
  const Image read = ReadImage(path);
  EXPECT_EQ(read.at(1, 1, 0), 65504.0f);
  EXPECT_EQ(read.at(2, 1, 1), -65504.0f);
  EXPECT_TRUE(std::isnan(read.at(3, 1, 2))) << "a NaN is a bug to find: it is kept";
}

TEST(Image, PngIsSrgbEncodedAndDecodedBack) {
  const Image image = Gradient(3);
  const auto path = TempPath("round_trip.png");
  WriteImage(image, path);
  const Image read = ReadImage(path);
  ASSERT_EQ(read.channels, 3);
  for (size_t i = 0; i < image.pixels.size(); ++i) {
    const float expected = std::clamp(image.pixels[i], 0.0f, 1.0f);
    // One 8-bit step of the sRGB curve, in linear terms, is at most ~0.0125.
    EXPECT_NEAR(read.pixels[i], expected, 0.0125f) << i;
  }
  // Linear 0.5 is stored as sRGB 188, not 128.
  Image grey(1, 1, 3);
  grey.pixels = {0.5f, 0.5f, 0.5f};
  WriteImage(grey, TempPath("grey.png"));
  EXPECT_NEAR(LinearToSrgb(0.5f) * 255.0f, 188.0f, 0.5f);
  EXPECT_NEAR(ReadImage(TempPath("grey.png")).pixels[0], SrgbToLinear(188.0f / 255.0f), 1e-6f);
}

TEST(Image, SrgbCurvesInvertEachOther) {
  for (float v = 0.0f; v <= 1.0f; v += 0.01f) EXPECT_NEAR(SrgbToLinear(LinearToSrgb(v)), v, 1e-5f);
}

TEST(Image, UnknownExtensionIsAClearError) {
  try {
    WriteImage(Gradient(3), TempPath("frame.bmpx"));
    FAIL();
  } catch (const Error& error) {
    EXPECT_EQ(error.code(), ErrorCode::kInvalidArgument);
    EXPECT_NE(std::string(error.what()).find("unsupported extension '.bmpx'"), std::string::npos) << error.what();
  }
  EXPECT_FALSE(std::filesystem::exists(TempPath("frame.bmpx")));
}

TEST(Image, MissingFileIsNotFound) {
  try {
    ReadImage(TempPath("does_not_exist.exr"));
    FAIL();
  } catch (const Error& error) {
    EXPECT_EQ(error.code(), ErrorCode::kNotFound);
  }
}

}  // namespace
}  // namespace loom
