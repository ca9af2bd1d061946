#include "core/animate/knit_simulation.h"

#include <gtest/gtest.h>

#include <cmath>

namespace loom::animate {
namespace {

TEST(KnitSimulation, AHangingClothComesToRestCarryingItsWeight) {
  const KnitCloth cloth = FlatKnitCloth(
      5, 8, 1.0f, 1.0f, glm::vec3(0), glm::vec3(1, 0, 0), glm::vec3(0, 0, -1));
  KnitSimulation sim(cloth, KnitMechanics{}, {});
  for (int i = 0; i < cloth.across; ++i)
    sim.Pin(cloth.Index(i, 0));
  sim.Advance(30.0f, 0.04f);
  EXPECT_LT(sim.KineticEnergy(), 1e-5);
  // The springs under the pinned course hold up the 5 × 7 free loops.
  const auto &x = sim.positions();
  glm::vec3 held(0.0f);
  for (int i = 0; i < cloth.across; ++i) {
    const glm::vec3 d = x[cloth.Index(i, 1)] - x[cloth.Index(i, 0)];
    held += SpringForce(KnitMechanics{}.wale, 1.0f, glm::length(d)) *
            glm::normalize(d);
  }
  EXPECT_NEAR(-held.z, 35 * 9.81f, 0.02f * 35 * 9.81f);
  // No course is pulled or pushed: their springs lie inside the balance
  // interval.
  for (int j = 0; j < cloth.along; ++j) {
    for (int i = 0; i + 1 < cloth.across; ++i) {
      const float length =
          glm::length(x[cloth.Index(i + 1, j)] - x[cloth.Index(i, j)]);
      EXPECT_GE(length, 0.95f - 1e-3f);
      EXPECT_LE(length, 1.05f + 1e-3f);
    }
  }
}

// A 4 × 4 patch resting at equilibrium in a slope's field, `degrees` steep; how
// far it moves in 2 s.
float SlideOnSlope(float degrees, float static_friction) {
  const float angle = glm::radians(degrees);
  const glm::vec3 normal(0, -std::sin(angle), std::cos(angle)),
      down(0, -std::cos(angle), -std::sin(angle));
  KnitMechanics mechanics;
  mechanics.static_friction = static_friction;
  const ThicknessField field(mechanics.half_thickness, mechanics.core,
                             mechanics.field_strength);
  const float depth = field.DistanceOf(9.81f * std::cos(angle));
  const KnitCloth cloth =
      FlatKnitCloth(4, 4, 1.0f, 1.0f, depth * normal + glm::vec3(-1.5f, 0, 0),
                    glm::vec3(1, 0, 0), -down);
  KnitSimulation sim(cloth, mechanics, {Collider::Plane(glm::vec3(0), normal)});
  const glm::vec3 start = sim.positions()[0];
  sim.Advance(2.0f, 0.04f);
  EXPECT_GE(sim.min_collider_distance(), 0.0f);
  return glm::length(sim.positions()[0] - start);
}

TEST(KnitSimulation, StaticFrictionHoldsBelowItsAngleAndLetsGoAbove) {
  // K_s = 1: held below 45°, sliding above (then under K_d = 0.5).
  EXPECT_LT(SlideOnSlope(40.0f, 1.0f), 1e-3f);
  EXPECT_GT(SlideOnSlope(50.0f, 1.0f), 1.0f);
  // Without static friction the 40° patch slides (tan 40° > K_d).
  EXPECT_GT(SlideOnSlope(40.0f, 0.0f), 1.0f);
}

// A 2 × 2 patch thrown at a floor at kSpeed loops/s from just outside its field
// (a full step lands below it); the least distance of a point from the floor
// over 1 s, and the simulation's counts.
constexpr float kSpeed = 30.0f;
KnitSimulation Thrown(int max_halvings) {
  KnitMechanics mechanics;
  mechanics.travel = 1e9f; // only the halving keeps the points out
  mechanics.max_halvings = max_halvings;
  const KnitCloth cloth =
      FlatKnitCloth(2, 2, 1.0f, 1.0f, glm::vec3(0, 0, 0.95f),
                    glm::vec3(1, 0, 0), glm::vec3(0, 1, 0));
  KnitSimulation sim(cloth, mechanics,
                     {Collider::Plane(glm::vec3(0), glm::vec3(0, 0, 1))});
  for (size_t p = 0; p < 4; ++p)
    sim.SetVelocity(p, glm::vec3(0, 0, -kSpeed));
  sim.Advance(1.0f, 0.04f);
  return sim;
}

TEST(KnitSimulation, TheHalvedStepPreventsAPenetrationTheFullStepMakes) {
  const KnitSimulation full = Thrown(0);
  EXPECT_LT(full.min_collider_distance(), 0.0f);
  EXPECT_GT(full.counts().penetrations, 0);
  const KnitSimulation halved = Thrown(12);
  EXPECT_GT(halved.min_collider_distance(), 0.0f);
  EXPECT_GT(halved.counts().halvings, 0);
  EXPECT_EQ(halved.counts().penetrations, 0);
  // It bounced: moving up, above the floor.
  EXPECT_GT(halved.positions()[0].z, 0.0f);
}

} // namespace
} // namespace loom::animate
