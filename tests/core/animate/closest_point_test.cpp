#include "core/animate/closest_point.h"

#include <gtest/gtest.h>

namespace loom::animate {
namespace {

constexpr glm::vec3 kA(0, 0, 0), kB(2, 0, 0), kC(0, 2, 0);

void ExpectNear(glm::vec3 got, glm::vec3 want) {
  EXPECT_NEAR(got.x, want.x, 1e-5f);
  EXPECT_NEAR(got.y, want.y, 1e-5f);
  EXPECT_NEAR(got.z, want.z, 1e-5f);
}

TEST(ClosestPointOnTriangle, FindsTheFaceEdgeOrCornerNearest) {
  // Above the face: straight down, weights of the foot.
  TrianglePoint q = ClosestPointOnTriangle(glm::vec3(0.5f, 0.5f, 3), kA, kB, kC);
  ExpectNear(q.point, glm::vec3(0.5f, 0.5f, 0));
  ExpectNear(q.weights, glm::vec3(0.5f, 0.25f, 0.25f));
  // Beyond the hypotenuse: its midpoint.
  q = ClosestPointOnTriangle(glm::vec3(2, 2, 1), kA, kB, kC);
  ExpectNear(q.point, glm::vec3(1, 1, 0));
  ExpectNear(q.weights, glm::vec3(0, 0.5f, 0.5f));
  // Beyond a corner.
  q = ClosestPointOnTriangle(glm::vec3(-1, -1, 0), kA, kB, kC);
  ExpectNear(q.point, kA);
  q = ClosestPointOnTriangle(glm::vec3(3, -1, 0), kA, kB, kC);
  ExpectNear(q.weights, glm::vec3(0, 1, 0));
  // Beside the edge AB.
  q = ClosestPointOnTriangle(glm::vec3(1.5f, -2, 0.5f), kA, kB, kC);
  ExpectNear(q.point, glm::vec3(1.5f, 0, 0));
}

TEST(ClosestPointOnTriangle, NoPointOfTheTriangleIsNearer) {
  // Brute force over a fine barycentric grid for scattered points.
  const glm::vec3 a(0.3f, -0.2f, 0.1f), b(1.7f, 0.4f, -0.5f), c(0.2f, 1.9f, 0.8f);
  for (int k = 0; k < 50; ++k) {
    const glm::vec3 p(std::sin(1.3f * k) * 3, std::cos(0.7f * k) * 3, std::sin(2.1f * k + 1) * 2);
    const TrianglePoint q = ClosestPointOnTriangle(p, a, b, c);
    EXPECT_NEAR(q.weights.x + q.weights.y + q.weights.z, 1.0f, 1e-5f);
    ExpectNear(q.point, q.weights.x * a + q.weights.y * b + q.weights.z * c);
    float best = 1e9f;
    for (int i = 0; i <= 100; ++i) {
      for (int j = 0; i + j <= 100; ++j) {
        const glm::vec3 s = a + (b - a) * (i / 100.0f) + (c - a) * (j / 100.0f);
        best = std::min(best, glm::distance(p, s));
      }
    }
    EXPECT_LE(glm::distance(p, q.point), best + 1e-5f);
    EXPECT_GE(glm::distance(p, q.point), best - 0.03f);
  }
}

TEST(ProjectedWeights, AreNegativeOutsideAndZeroForADegenerateTriangle) {
  ExpectNear(ProjectedWeights(glm::vec3(0.5f, 0.5f, 7), kA, kB, kC), glm::vec3(0.5f, 0.25f, 0.25f));
  EXPECT_LT(ProjectedWeights(glm::vec3(3, 3, 0), kA, kB, kC).x, 0.0f);
  ExpectNear(ProjectedWeights(glm::vec3(1, 1, 1), kA, kB, 2.0f * kB), glm::vec3(0.0f));
}

}  // namespace
}  // namespace loom::animate
