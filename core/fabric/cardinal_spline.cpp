#include "core/fabric/cardinal_spline.h"

#include <cassert>

namespace loom {

template <typename T>
std::vector<SplineSample<T>> SamplePeriodicCardinalSpline(std::span<const T> keys, T period, float tension,
                                                          int samples_per_segment) {
  assert(keys.size() >= 2 && samples_per_segment >= 1);
  const int n = static_cast<int>(keys.size());
  // Key i for any integer i, shifted by whole periods.
  auto key = [&](int i) {
    const int wraps = (i >= 0 ? i : i - n + 1) / n;
    return keys[static_cast<size_t>(i - wraps * n)] + static_cast<float>(wraps) * period;
  };
  const float scale = 0.5f * (1.0f - tension);
  std::vector<SplineSample<T>> samples;
  samples.reserve(static_cast<size_t>(n) * samples_per_segment + 1);
  for (int i = 0; i < n; ++i) {
    const T p0 = key(i), p1 = key(i + 1);
    const T m0 = scale * (p1 - key(i - 1));
    const T m1 = scale * (key(i + 2) - p0);
    for (int s = 0; s < samples_per_segment; ++s) {
      const float t = static_cast<float>(s) / static_cast<float>(samples_per_segment);
      const float t2 = t * t, t3 = t2 * t;
      // Cubic Hermite basis and its derivative.
      const float h00 = 2 * t3 - 3 * t2 + 1, h10 = t3 - 2 * t2 + t, h01 = -2 * t3 + 3 * t2, h11 = t3 - t2;
      const float d00 = 6 * t2 - 6 * t, d10 = 3 * t2 - 4 * t + 1, d01 = -6 * t2 + 6 * t, d11 = 3 * t2 - 2 * t;
      samples.push_back({h00 * p0 + h10 * m0 + h01 * p1 + h11 * m1, d00 * p0 + d10 * m0 + d01 * p1 + d11 * m1});
    }
  }
  // The closing sample is the first one moved by exactly one period (same tangent).
  samples.push_back({samples.front().position + period, samples.front().derivative});
  return samples;
}

template std::vector<SplineSample<float>> SamplePeriodicCardinalSpline(std::span<const float>, float, float, int);
template std::vector<SplineSample<glm::vec3>> SamplePeriodicCardinalSpline(std::span<const glm::vec3>, glm::vec3,
                                                                           float, int);

}  // namespace loom
