#include "core/animate/knit_forces.h"

#include <gtest/gtest.h>

#include <cmath>

namespace loom::animate {
namespace {

TEST(SpringLaw, NoForceInsideTheBalanceIntervalAndContinuousAtItsEnds) {
  const SpringLaw law{1500.0f, 3000.0f};
  const float rest = 1.3f;
  for (float x = 0.95f; x <= 1.05f; x += 0.001f) {
    EXPECT_EQ(SpringForce(law, rest, x * rest), 0.0f) << x;
    EXPECT_EQ(SpringStiffness(law, rest, x * rest), 0.0f) << x;
  }
  // Just past either end the force starts from zero (the paper's e^{x−1} would
  // start at c₀/e).
  EXPECT_NEAR(SpringForce(law, rest, 1.05f * rest * 1.0001f), 0.0f, 0.2f);
  EXPECT_NEAR(SpringForce(law, rest, 0.95f * rest * 0.9999f), 0.0f, 0.4f);
  // Stretched by x beyond θ₁ it pulls with c₀(e^x − 1); compressed it pushes.
  EXPECT_NEAR(SpringForce(law, rest, 1.05f * rest * 1.2f), 1500.0f * std::expm1(0.2f), 0.05f);
  EXPECT_NEAR(SpringForce(law, rest, 0.95f * rest * 0.9f), -3000.0f * std::expm1(0.1f), 0.05f);
  // The stiffness is the force's slope.
  const float l = 1.05f * rest * 1.1f, h = 1e-3f;
  EXPECT_NEAR(SpringStiffness(law, rest, l), (SpringForce(law, rest, l + h) - SpringForce(law, rest, l - h)) / (2 * h),
              1.0f);
}

TEST(ThicknessField, ContinuousWithItsSlopeAtTheCoreAndABarrierAtTheCentre) {
  const ThicknessField field(0.9f, 0.1f, 100.0f);
  const float tau = 0.1f, e = 1e-5f;
  EXPECT_NEAR(field(tau - e), field(tau + e), 0.01f);
  EXPECT_NEAR(field.Slope(tau - e), field.Slope(tau + e), 0.1f);
  EXPECT_FLOAT_EQ(field(tau + e), 100.0f * (0.8f - e) * (0.8f - e));
  EXPECT_EQ(field(0.9f), 0.0f);
  EXPECT_EQ(field(2.0f), 0.0f);
  EXPECT_NEAR(field(0.9f - e), 0.0f, 1e-6f);
  // Below the core it keeps rising, without bound as d → 0.
  EXPECT_GT(field(0.05f), field(0.1f));
  EXPECT_GT(field(0.001f), 1e6f);
  // The paper's constants (c₆ = c₅) are not continuous at τ: the derived c₆
  // differs.
  EXPECT_LT(field.c6(), 0.8f * 100.0f);
  for (float force : {1.0f, 9.81f, 50.0f, 500.0f}) EXPECT_NEAR(field(field.DistanceOf(force)), force, 1e-3f * force);
}

TEST(AngleForces, AddUpToZeroWithoutTorqueAndFollowTheAngle) {
  const glm::vec3 a(0, 0, 0), b(1, 0, 0), c(1.0f + std::cos(0.3f), std::sin(0.3f), 0);
  const auto bend = BendForces(a, b, c, 100.0f, 1.0f);
  EXPECT_NEAR(glm::length(bend[0] + bend[1] + bend[2]), 0.0f, 1e-4f);
  EXPECT_NEAR(glm::length(glm::cross(a, bend[0]) + glm::cross(b, bend[1]) + glm::cross(c, bend[2])), 0.0f, 1e-3f);
  // Unit arms: each end feels constant × angle, towards straightening.
  EXPECT_NEAR(glm::length(bend[0]), 30.0f, 1e-3f);
  EXPECT_NEAR(glm::length(bend[2]), 30.0f, 1e-3f);
  // Bent upwards at b: the ends go down, b up.
  EXPECT_LT(bend[0].y, 0.0f);
  EXPECT_LT(bend[2].y, 0.0f);
  EXPECT_GT(bend[1].y, 0.0f);
  // Straight: none.
  const auto straight = BendForces(a, b, glm::vec3(2, 0, 0), 100.0f, 1.0f);
  EXPECT_EQ(glm::length(straight[1]), 0.0f);
  // A corner sheared from its right angle is pushed back.
  const auto shear = ShearForces(glm::vec3(1, 0, 0), glm::vec3(0), glm::vec3(std::sin(0.2f), std::cos(0.2f), 0),
                                 1.5707964f, 1000.0f, 1.0f);
  EXPECT_NEAR(glm::length(shear[0] + shear[1] + shear[2]), 0.0f, 1e-3f);
  EXPECT_NEAR(glm::length(shear[0]), 200.0f, 0.1f);
  EXPECT_LT(shear[2].x, 0.0f);  // opened back towards 90°
}

}  // namespace
}  // namespace loom::animate
