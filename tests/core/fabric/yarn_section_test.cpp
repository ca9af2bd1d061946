// The yarn's cross-section density (core/fabric/yarn_section.h): Zhao et al.'s fibre
// distribution in each ply, plies packed inside the yarn, flyaways outside it.

#include "core/fabric/yarn_section.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace loom {
namespace {

YarnSection SectionOf(uint32_t plies, float fuzz) {
  v1::YarnSpec yarn;
  yarn.set_plies(plies);
  yarn.set_fuzz(fuzz);
  return MakeYarnSection(yarn);
}

TEST(YarnSection, APlyHoldsZhaosDistributionFromItsCentreToItsEdge) {
  const float e = std::numbers::e_v<float>, eps = kFibreDensityEpsilon, beta = kFibreDensityBeta;
  EXPECT_NEAR(PlyFibreDensity(0.0f), 1.0f - eps, 1e-6f);
  EXPECT_NEAR(PlyFibreDensity(1.0f), eps, 1e-6f);
  EXPECT_NEAR(PlyFibreDensity(0.5f), (1 - 2 * eps) * std::pow((e - std::sqrt(e)) / (e - 1), beta) + eps, 1e-6f);
  EXPECT_EQ(PlyFibreDensity(1.001f), 0.0f);
  for (float r = 0.0f; r < 1.0f; r += 0.05f) EXPECT_GT(PlyFibreDensity(r), PlyFibreDensity(r + 0.05f)) << r;
}

TEST(YarnSection, OnePlyWithoutFuzzIsTheYarnsDisk) {
  const YarnSection one = SectionOf(1, 0.0f);
  EXPECT_EQ(one.extent(), 1.0f);
  EXPECT_NEAR(FibreDensity(one, {0.0f, 0.0f}), 1.0f - kFibreDensityEpsilon, 1e-6f);
  EXPECT_NEAR(FibreDensity(one, {0.0f, 0.999f}), PlyFibreDensity(0.999f), 1e-6f);
  EXPECT_EQ(FibreDensity(one, {0.72f, 0.72f}), 0.0f);  // |p| > 1
}

// Plies are the largest equal circles that fit in the yarn touching their neighbours:
// their centres are 1 − r from the yarn's, neighbours touch half-way, and the yarn's
// centre is empty from three plies on.
TEST(YarnSection, PliesArePackedInsideTheYarnTouchingTheirNeighbours) {
  for (const uint32_t plies : {2u, 3u, 4u, 6u, 8u}) {
    const YarnSection section = SectionOf(plies, 0.0f);
    const float angle = std::numbers::pi_v<float> / static_cast<float>(plies);
    EXPECT_NEAR(section.ply_offset * std::sin(angle), section.ply_radius, 1e-5f) << plies;  // neighbours touch
    EXPECT_NEAR(section.ply_offset + section.ply_radius, 1.0f, 1e-6f) << plies;           // the yarn's edge
    for (uint32_t k = 0; k < plies; ++k) {
      const float at = 2.0f * angle * static_cast<float>(k);
      const glm::vec2 centre = section.ply_offset * glm::vec2(std::cos(at), std::sin(at));
      EXPECT_NEAR(FibreDensity(section, centre), 1.0f - kFibreDensityEpsilon, 1e-5f) << plies << " ply " << k;
      // Where two neighbours touch, both edges: a step towards this ply's centre is in it.
      const glm::vec2 touch = section.ply_offset * std::cos(angle) * glm::vec2(std::cos(at + angle), std::sin(at + angle));
      EXPECT_NEAR(glm::length(touch - centre), section.ply_radius, 1e-5f) << plies << " touch " << k;
      EXPECT_NEAR(FibreDensity(section, touch + 0.001f * (centre - touch)), PlyFibreDensity(0.999f), 1e-3f)
          << plies << " touch " << k;
    }
    if (plies >= 3) EXPECT_EQ(FibreDensity(section, {0.0f, 0.0f}), 0.0f) << plies;
  }
}

TEST(YarnSection, TheTwistTurnsTheSection) {
  const YarnSection three = SectionOf(3, 0.3f);
  const glm::vec2 p(0.41f, 0.17f);
  const float phase = 0.7f;
  const glm::vec2 turned_back(std::cos(-phase) * p.x - std::sin(-phase) * p.y,
                              std::sin(-phase) * p.x + std::cos(-phase) * p.y);
  EXPECT_NEAR(FibreDensity(three, p, phase), FibreDensity(three, turned_back), 1e-5f);
  EXPECT_NE(FibreDensity(three, p, phase), FibreDensity(three, p));
}

TEST(YarnSection, FuzzAddsFlyawaysOutsideTheYarnFallingOff) {
  const YarnSection fuzzy = SectionOf(1, 0.5f);
  EXPECT_EQ(fuzzy.extent(), 1.5f);
  EXPECT_NEAR(FibreDensity(fuzzy, {1.0001f, 0.0f}), 0.5f * kFibreDensityEpsilon, 1e-4f);
  EXPECT_NEAR(FibreDensity(fuzzy, {0.0f, -1.5f}), 0.5f * kFibreDensityEpsilon * std::exp(-3.0f), 1e-6f);
  EXPECT_GT(FibreDensity(fuzzy, {1.1f, 0.0f}), FibreDensity(fuzzy, {1.3f, 0.0f}));
  EXPECT_EQ(FibreDensity(fuzzy, {1.51f, 0.0f}), 0.0f);
  EXPECT_EQ(FibreDensity(SectionOf(1, 0.0f), {1.1f, 0.0f}), 0.0f);
}

// The grid's fibres are the distribution's: its sum times a cell's area is the plies'
// integral ∫ p(r) 2πr dr · r_ply² · K (Simpson's rule here) plus the flyaways' ring.
TEST(YarnSection, TheGridHoldsTheSectionsFibres) {
  double ply = 0.0;
  const int n = 2000;
  for (int i = 0; i <= n; ++i) {
    const double r = static_cast<double>(i) / n, weight = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
    ply += weight * PlyFibreDensity(static_cast<float>(r)) * 2.0 * std::numbers::pi * r;
  }
  ply /= 3.0 * n;
  for (const uint32_t plies : {1u, 3u, 5u}) {
    const YarnSection section = SectionOf(plies, 0.0f);
    const int resolution = 256;
    double sum = 0.0;
    for (const float d : SectionDensityGrid(section, resolution)) sum += d;
    const double cell = 2.0 * section.extent() / resolution;
    const double expected = ply * plies * section.ply_radius * section.ply_radius;
    EXPECT_NEAR(sum * cell * cell, expected, 0.01 * expected) << plies;
  }
}

}  // namespace
}  // namespace loom
