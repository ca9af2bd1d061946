#include "core/fabric/cardinal_spline.h"

#include <gtest/gtest.h>

#include <vector>

namespace loom {
namespace {

TEST(CardinalSpline, PassesThroughKeysAndSpansOnePeriod) {
  const std::vector<glm::vec3> keys = {{0.1f, 0, 0}, {0.4f, 0.3f, 0.2f}, {0.7f, -0.1f, -0.3f}};
  const glm::vec3 period(1, 0, 0);
  const auto samples = SamplePeriodicCardinalSpline<glm::vec3>(keys, period, 0.0f, 5);
  ASSERT_EQ(samples.size(), 3u * 5 + 1);
  for (size_t i = 0; i < keys.size(); ++i) EXPECT_EQ(samples[i * 5].position, keys[i]);
  EXPECT_EQ(samples.back().position, keys[0] + period);
  EXPECT_EQ(samples.back().derivative, samples.front().derivative);
}

TEST(CardinalSpline, CatmullRomTangentIsHalfTheNeighbourChord) {
  // Key 0's neighbours are key 2 moved back by the period and key 1.
  const std::vector<glm::vec3> keys = {{0, 0, 0}, {0.25f, 1, 0}, {0.5f, 0, 0}, {0.75f, -1, 0}};
  const glm::vec3 period(1, 0, 0);
  const auto catmull_rom = SamplePeriodicCardinalSpline<glm::vec3>(keys, period, 0.0f, 4);
  const glm::vec3 expected = 0.5f * (keys[1] - (keys[3] - period));
  EXPECT_NEAR(glm::distance(catmull_rom[0].derivative, expected), 0.0f, 1e-6f);
  // Tension scales the tangents by (1 - tension); at 1 the curve rests on each key.
  const auto tense = SamplePeriodicCardinalSpline<glm::vec3>(keys, period, 0.5f, 4);
  EXPECT_NEAR(glm::distance(tense[0].derivative, 0.5f * expected), 0.0f, 1e-6f);
  const auto flat = SamplePeriodicCardinalSpline<glm::vec3>(keys, period, 1.0f, 4);
  for (size_t i = 0; i < keys.size(); ++i) EXPECT_EQ(flat[i * 4].derivative, glm::vec3(0.0f));
}

TEST(CardinalSpline, IsC1AcrossSegments) {
  const std::vector<float> heights = {1, 1, -1, 1, -1};
  const auto samples = SamplePeriodicCardinalSpline<float>(heights, 0.0f, 0.3f, 256);
  for (size_t i = 1; i + 1 < samples.size(); ++i) {
    // Finite differences agree with the derivative everywhere, key points included
    // (where the second derivative jumps: first-order error there).
    const float slope = (samples[i + 1].position - samples[i - 1].position) * 128.0f;
    EXPECT_NEAR(slope, samples[i].derivative, 0.01f) << i;
  }
}

}  // namespace
}  // namespace loom
