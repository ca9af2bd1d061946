#include "tests/core/render/image_probes.h"

namespace loom::testing {

double RedFraction(const Image& image) {
  int red = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) red += image.at(x, y, 0) > 1.5f * image.at(x, y, 1) + 1e-3f;
  return static_cast<double>(red) / (image.width * image.height);
}

double MeanRedExcess(const Image& image) {
  double sum = 0.0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) sum += image.at(x, y, 0) - image.at(x, y, 1);
  return sum / (image.width * image.height);
}

double MeanRedInColumns(const Image& image, int x0, int x1) {
  double sum = 0.0;
  for (int y = 0; y < image.height; ++y)
    for (int x = x0; x < x1; ++x) sum += image.at(x, y, 0);
  return sum / (double(x1 - x0) * image.height);
}

}  // namespace loom::testing
