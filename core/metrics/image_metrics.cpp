#include "core/metrics/image_metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/util/error.h"

namespace loom {
namespace {

void CheckComparable(const Image& a, const Image& b) {
  if (a.width != b.width || a.height != b.height) {
    throw Error(ErrorCode::kInvalidArgument, "images differ in size: " + std::to_string(a.width) + "x" +
                                                 std::to_string(a.height) + " vs " + std::to_string(b.width) + "x" +
                                                 std::to_string(b.height));
  }
  if (a.channels < 3 || b.channels < 3) {
    throw Error(ErrorCode::kInvalidArgument, "images need RGB channels to be compared");
  }
}

// SSIM of one window of the luminance planes.
double WindowSsim(const std::vector<double>& a, const std::vector<double>& b, int width, int x0, int y0, int size,
                  double c1, double c2) {
  double mean_a = 0, mean_b = 0;
  for (int y = y0; y < y0 + size; ++y)
    for (int x = x0; x < x0 + size; ++x) {
      mean_a += a[static_cast<size_t>(y) * width + x];
      mean_b += b[static_cast<size_t>(y) * width + x];
    }
  const double n = static_cast<double>(size) * size;
  mean_a /= n;
  mean_b /= n;
  double var_a = 0, var_b = 0, covariance = 0;
  for (int y = y0; y < y0 + size; ++y)
    for (int x = x0; x < x0 + size; ++x) {
      const double da = a[static_cast<size_t>(y) * width + x] - mean_a;
      const double db = b[static_cast<size_t>(y) * width + x] - mean_b;
      var_a += da * da;
      var_b += db * db;
      covariance += da * db;
    }
  var_a /= n - 1;
  var_b /= n - 1;
  covariance /= n - 1;
  return ((2 * mean_a * mean_b + c1) * (2 * covariance + c2)) /
         ((mean_a * mean_a + mean_b * mean_b + c1) * (var_a + var_b + c2));
}

std::vector<double> LuminancePlane(const Image& image) {
  std::vector<double> plane(static_cast<size_t>(image.width) * image.height);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) plane[static_cast<size_t>(y) * image.width + x] = Luminance(image, x, y);
  return plane;
}

}  // namespace

double Luminance(const Image& image, int x, int y) {
  // Rec. 709 / sRGB primaries.
  return 0.2126 * image.at(x, y, 0) + 0.7152 * image.at(x, y, 1) + 0.0722 * image.at(x, y, 2);
}

ImageComparison CompareImages(const Image& test, const Image& reference) {
  CheckComparable(test, reference);
  ImageComparison result;
  result.width = test.width;
  result.height = test.height;
  double squared = 0.0, test_sum = 0.0, reference_sum = 0.0;
  for (int y = 0; y < test.height; ++y)
    for (int x = 0; x < test.width; ++x) {
      bool finite = true;
      for (int c = 0; c < 3; ++c) {
        const double a = test.at(x, y, c), b = reference.at(x, y, c);
        finite = finite && std::isfinite(a) && std::isfinite(b);
        squared += (a - b) * (a - b);
        test_sum += a;
        reference_sum += b;
        if (std::isfinite(b)) result.peak = std::max(result.peak, b);
      }
      if (!finite) ++result.non_finite_pixels;
    }
  if (result.non_finite_pixels > 0) {
    // No figure describes such a pair; NaN keeps any mean or chart built on them honest.
    result.rmse = result.psnr_db = result.ssim = result.mean_ratio = std::numeric_limits<double>::quiet_NaN();
    return result;
  }
  result.mean_ratio = reference_sum > 0.0   ? test_sum / reference_sum
                      : test_sum == 0.0 ? 1.0
                                        : std::numeric_limits<double>::infinity();
  const double mse = squared / (3.0 * test.width * test.height);
  result.rmse = std::sqrt(mse);
  const double peak = result.peak > 0.0 ? result.peak : 1.0;
  result.psnr_db = mse > 0.0 ? 10.0 * std::log10(peak * peak / mse) : std::numeric_limits<double>::infinity();

  constexpr int kWindow = 8, kStride = 4;
  const double c1 = (0.01 * peak) * (0.01 * peak), c2 = (0.03 * peak) * (0.03 * peak);
  const std::vector<double> a = LuminancePlane(test), b = LuminancePlane(reference);
  double sum = 0.0;
  int windows = 0;
  for (int y = 0; y + kWindow <= test.height; y += kStride)
    for (int x = 0; x + kWindow <= test.width; x += kStride) {
      sum += WindowSsim(a, b, test.width, x, y, kWindow, c1, c2);
      ++windows;
    }
  result.ssim = windows > 0 ? sum / windows : (mse == 0.0 ? 1.0 : 0.0);
  return result;
}

Image ErrorHeatMap(const Image& test, const Image& reference, double scale) {
  CheckComparable(test, reference);
  std::vector<double> error(static_cast<size_t>(test.width) * test.height);
  double largest = 0.0;
  for (int y = 0; y < test.height; ++y)
    for (int x = 0; x < test.width; ++x) {
      double squared = 0.0;
      for (int c = 0; c < 3; ++c) {
        const double d = static_cast<double>(test.at(x, y, c)) - reference.at(x, y, c);
        squared += d * d;
      }
      error[static_cast<size_t>(y) * test.width + x] = std::sqrt(squared / 3.0);
      largest = std::max(largest, error[static_cast<size_t>(y) * test.width + x]);
    }
  const double white = scale > 0.0 ? scale : (largest > 0.0 ? largest : 1.0);
  // Control points of the ramp, evenly spaced in t; values are linear RGB.
  static constexpr float kRamp[5][3] = {{0, 0, 0}, {0.02f, 0.05f, 0.6f}, {0.6f, 0.05f, 0.5f}, {1, 0.75f, 0.05f}, {1, 1, 1}};
  Image heat(test.width, test.height, 3);
  for (int y = 0; y < test.height; ++y)
    for (int x = 0; x < test.width; ++x) {
      const double t = std::clamp(error[static_cast<size_t>(y) * test.width + x] / white, 0.0, 1.0) * 4.0;
      const int i = std::min(static_cast<int>(t), 3);
      const float f = static_cast<float>(t - i);
      for (int c = 0; c < 3; ++c) heat.at(x, y, c) = kRamp[i][c] * (1 - f) + kRamp[i + 1][c] * f;
    }
  return heat;
}

double TemporalFlicker(const std::vector<Image>& frames, int dx, int dy) {
  double sum = 0.0;
  size_t count = 0;
  for (size_t k = 0; k + 1 < frames.size(); ++k) {
    const Image& previous = frames[k];
    const Image& next = frames[k + 1];
    CheckComparable(previous, next);
    for (int y = 0; y < next.height; ++y)
      for (int x = 0; x < next.width; ++x) {
        const int px = x - dx, py = y - dy;
        if (px < 0 || py < 0 || px >= previous.width || py >= previous.height) continue;
        sum += std::abs(Luminance(next, x, y) - Luminance(previous, px, py));
        ++count;
      }
  }
  return count > 0 ? sum / static_cast<double>(count) : 0.0;
}

}  // namespace loom
