#include "core/acquire/hemisphere_directions.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <glm/gtc/constants.hpp>
#include <random>

#include "core/util/error.h"

namespace loom {
namespace {

TEST(HemisphereDirections, GridDirectionsAreUnitAboveTheHorizonAndRoundTripToTheirCells) {
  for (uint32_t side : {2u, 3u, 8u, 64u}) {
    const std::vector<glm::vec3> directions = HemisphereGridDirections(side * side);
    ASSERT_EQ(directions.size(), side * side);
    for (uint32_t row = 0; row < side; ++row) {
      for (uint32_t col = 0; col < side; ++col) {
        const glm::vec3 d = directions[row * side + col];
        EXPECT_NEAR(glm::length(d), 1.0f, 1e-6f);
        EXPECT_GT(d.z, 0.0f);
        const glm::vec2 g = HemisphereGridCoordinates(d, side);
        EXPECT_NEAR(g.x, col, 1e-6f * side) << side << " " << row << " " << col;
        EXPECT_NEAR(g.y, row, 1e-6f * side) << side << " " << row << " " << col;
      }
    }
  }
}

TEST(HemisphereDirections, OddGridsHaveTheZenithAtTheCentreAndAxesWhereTheDocsSay) {
  const auto directions = HemisphereGridDirections(9);
  EXPECT_EQ(directions[4], glm::vec3(0, 0, 1));
  // u → +x, v → +y.
  EXPECT_GT(directions[5].x, 0.5f);
  EXPECT_NEAR(directions[5].y, 0.0f, 1e-6f);
  EXPECT_GT(directions[7].y, 0.5f);
  EXPECT_NEAR(directions[7].x, 0.0f, 1e-6f);
}

TEST(HemisphereDirections, InverseMapRoundTripsEverywhereIncludingCentreEdgesAndDiagonals) {
  float worst = 0.0f;
  for (int j = 0; j <= 200; ++j) {
    for (int i = 0; i <= 200; ++i) {
      const glm::vec2 square(i / 200.0f, j / 200.0f);
      const glm::vec3 d = SquareToHemisphere(square);
      ASSERT_NEAR(glm::length(d), 1.0f, 1e-5f);
      ASSERT_GE(d.z, 0.0f);
      const glm::vec2 back = HemisphereToSquare(d);
      worst = std::max(worst, glm::length(back - square));
      // And the other way round: direction → square → direction.
      ASSERT_LT(glm::length(SquareToHemisphere(back) - d), 1e-4f);
    }
  }
  EXPECT_LT(worst, 1e-5f);
}

TEST(HemisphereDirections, CoversTheHemisphereEvenly) {
  // Uniform random directions land in [0,1]² and fall into every cell of an 8×8
  // grid about equally often (equal-area map).
  std::mt19937 generator(7);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  constexpr int kSide = 8, kSamples = 640000;
  std::vector<int> counts(kSide * kSide, 0);
  const auto grid = HemisphereGridDirections(kSide * kSide);
  float farthest = 0.0f;  // the largest angle from a direction to its nearest grid direction
  for (int n = 0; n < kSamples; ++n) {
    const float z = uniform(generator), phi = glm::two_pi<float>() * uniform(generator);
    const float s = std::sqrt(1.0f - z * z);
    const glm::vec3 d(s * std::cos(phi), s * std::sin(phi), z);
    const glm::vec2 square = HemisphereToSquare(d);
    ASSERT_TRUE(square.x >= 0 && square.x <= 1 && square.y >= 0 && square.y <= 1);
    const int col = std::min(static_cast<int>(square.x * kSide), kSide - 1);
    const int row = std::min(static_cast<int>(square.y * kSide), kSide - 1);
    ++counts[row * kSide + col];
    if (n % 64 == 0) {
      float best = -1.0f;
      for (const glm::vec3& g : grid) best = std::max(best, glm::dot(g, d));
      farthest = std::max(farthest, std::acos(std::min(best, 1.0f)));
    }
  }
  const float expected = static_cast<float>(kSamples) / (kSide * kSide);
  for (int count : counts) EXPECT_NEAR(count, expected, 0.05f * expected);
  // No direction is farther than ~one cell diagonal from a grid direction (8×8:
  // cells of 2π/64 sr, about 18° across; the outer ring's centres sit 13° above
  // the horizon).
  EXPECT_LT(glm::degrees(farthest), 20.0f);
}

TEST(HemisphereDirections, HorizonMapsToTheBorderAndBelowHorizonIsProjected) {
  for (float phi = 0.0f; phi < 6.28f; phi += 0.1f) {
    const glm::vec2 square = HemisphereToSquare({std::cos(phi), std::sin(phi), 0.0f});
    const float border = std::max(std::abs(2 * square.x - 1), std::abs(2 * square.y - 1));
    EXPECT_NEAR(border, 1.0f, 1e-5f);
    EXPECT_EQ(HemisphereToSquare({std::cos(phi), std::sin(phi), -0.3f}), square);
  }
  EXPECT_EQ(HemisphereToSquare(glm::vec3(0.0f)), glm::vec2(0.5f));
}

TEST(HemisphereDirections, NonSquareCountsAreRejected) {
  EXPECT_EQ(HemisphereGridSide(64), 8u);
  EXPECT_THROW(HemisphereGridSide(0), Error);
  EXPECT_THROW(HemisphereGridDirections(10), Error);
}

}  // namespace
}  // namespace loom
