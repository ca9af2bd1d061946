#include "core/metrics/image_metrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "core/util/error.h"

namespace loom {
namespace {

Image Pattern(int width, int height, int offset_x = 0) {
  Image image(width, height, 3);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < 3; ++c)
        image.at(x, y, c) = 0.5f + 0.4f * std::sin(0.7f * (x - offset_x) + 0.3f * y + c);
  return image;
}

TEST(ImageMetrics, IdenticalImagesHaveNoError) {
  const Image a = Pattern(32, 24);
  const ImageComparison result = CompareImages(a, a);
  EXPECT_EQ(result.rmse, 0.0);
  EXPECT_TRUE(std::isinf(result.psnr_db));
  EXPECT_NEAR(result.ssim, 1.0, 1e-12);
}

TEST(ImageMetrics, ConstantOffsetGivesKnownRmseAndPsnr) {
  Image reference(16, 16, 3), test(16, 16, 3);
  for (float& v : reference.pixels) v = 1.0f;
  for (float& v : test.pixels) v = 0.9f;
  const ImageComparison result = CompareImages(test, reference);
  EXPECT_NEAR(result.rmse, 0.1, 1e-6);
  EXPECT_NEAR(result.psnr_db, 20.0, 1e-4);  // peak 1, MSE 0.01
  EXPECT_EQ(result.peak, 1.0);
  EXPECT_NEAR(result.mean_ratio, 0.9, 1e-6);
  EXPECT_EQ(CompareImages(reference, reference).mean_ratio, 1.0);
}

TEST(ImageMetrics, NonFinitePixelsAreCountedAndGiveNoScore) {
  const Image reference = Pattern(16, 16);
  Image test = reference;
  test.at(3, 4, 1) = std::numeric_limits<float>::quiet_NaN();
  test.at(5, 6, 0) = std::numeric_limits<float>::infinity();
  test.at(5, 6, 2) = -std::numeric_limits<float>::infinity();  // the same pixel: counted once
  const ImageComparison result = CompareImages(test, reference);
  EXPECT_EQ(result.non_finite_pixels, 2u);
  // Before the count, the NaN difference read as no error at all: PSNR +inf.
  EXPECT_TRUE(std::isnan(result.psnr_db));
  EXPECT_TRUE(std::isnan(result.rmse));
  EXPECT_TRUE(std::isnan(result.ssim));
  EXPECT_TRUE(std::isnan(result.mean_ratio));
  // A NaN in the reference counts too, and its peak stays the finite values' largest.
  const ImageComparison swapped = CompareImages(reference, test);
  EXPECT_EQ(swapped.non_finite_pixels, 2u);
  EXPECT_TRUE(std::isnan(swapped.psnr_db));
  EXPECT_TRUE(std::isfinite(swapped.peak));
  EXPECT_GT(swapped.peak, 0.0);
  EXPECT_EQ(CompareImages(reference, reference).non_finite_pixels, 0u);
}

TEST(ImageMetrics, SsimFallsAsNoiseGrows) {
  const Image reference = Pattern(64, 64);
  std::mt19937 random(7);
  double previous = 1.0;
  for (float sigma : {0.01f, 0.05f, 0.2f, 0.5f}) {
    Image noisy = reference;
    std::normal_distribution<float> noise(0.0f, sigma);
    for (float& v : noisy.pixels) v += noise(random);
    const double ssim = CompareImages(noisy, reference).ssim;
    EXPECT_LT(ssim, previous) << sigma;
    EXPECT_GT(ssim, -1.0);
    previous = ssim;
  }
  EXPECT_LT(previous, 0.6);
}

TEST(ImageMetrics, SizeMismatchIsAClearError) {
  try {
    CompareImages(Pattern(8, 8), Pattern(8, 9));
    FAIL();
  } catch (const Error& error) {
    EXPECT_EQ(std::string(error.what()), "images differ in size: 8x8 vs 8x9");
  }
}

TEST(ImageMetrics, HeatMapIsBlackWithoutErrorAndWhiteAtTheLargest) {
  const Image reference = Pattern(8, 8);
  Image test = reference;
  test.at(3, 4, 1) += 0.5f;
  const Image heat = ErrorHeatMap(test, reference);
  EXPECT_EQ(heat.at(0, 0, 0), 0.0f);
  for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(heat.at(3, 4, c), 1.0f);
}

TEST(ImageMetrics, FlickerIsZeroForAPureShiftAndPositiveForFlashing) {
  // Frame k is the pattern moved k pixels to the right: undoing the shift matches exactly.
  std::vector<Image> moving = {Pattern(32, 16, 0), Pattern(32, 16, 1), Pattern(32, 16, 2)};
  EXPECT_NEAR(TemporalFlicker(moving, 1, 0), 0.0, 1e-6);
  // The same frames compared without undoing the shift differ.
  EXPECT_GT(TemporalFlicker(moving, 0, 0), 0.05);
  // A frame that flashes brighter flickers by the flash's luminance.
  Image bright = Pattern(32, 16);
  for (float& v : bright.pixels) v += 0.25f;
  EXPECT_NEAR(TemporalFlicker({Pattern(32, 16), bright}, 0, 0), 0.25, 1e-5);
}

}  // namespace
}  // namespace loom
