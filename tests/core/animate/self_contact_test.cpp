#include "core/animate/self_contact.h"

#include <gtest/gtest.h>

#include <set>
#include <utility>

#include "core/animate/closest_point.h"
#include "core/util/error.h"

namespace loom::animate {
namespace {

// A 5 × 12 strip whose second half is folded back over its first, `gap` above.
KnitCloth FoldedStrip(float gap) {
  KnitCloth cloth = FlatKnitCloth(5, 12, 1.0f, 1.0f, glm::vec3(0), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0));
  for (int j = 6; j < 12; ++j) {
    for (int i = 0; i < 5; ++i) cloth.positions[cloth.Index(i, j)] = glm::vec3(i, 11 - j, gap);
  }
  return cloth;
}

// Every (point, triangle) outside the point's `rings` within `reach`, by brute force.
std::set<std::pair<uint32_t, uint32_t>> Within(const KnitCloth& cloth, const std::vector<glm::vec3>& x, float reach,
                                               int rings) {
  std::set<std::pair<uint32_t, uint32_t>> within;
  const auto triangles = cloth.Triangles();
  for (uint32_t p = 0; p < x.size(); ++p) {
    for (uint32_t t = 0; t < triangles.size(); ++t) {
      if (cloth.Adjacent(p, t, rings)) continue;
      const glm::uvec3 c = triangles[t];
      if (glm::distance(x[p], ClosestPointOnTriangle(x[p], x[c.x], x[c.y], x[c.z]).point) < reach) {
        within.emplace(p, t);
      }
    }
  }
  return within;
}

TEST(SelfContactPairs, AFlatClothTouchesNothingOutsideItsNeighbourhoods) {
  const KnitCloth cloth = FlatKnitCloth(8, 8, 1.0f, 1.0f, glm::vec3(0), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0));
  SelfContactPairs pairs(cloth, 1.2f, 0.5f, 2);
  pairs.Update(cloth.positions);
  EXPECT_TRUE(pairs.pairs().empty());
  // Excluding only the triangles at the point, the next ring lies 1 away.
  SelfContactPairs all(cloth, 1.2f, 0.5f, 0);
  all.Update(cloth.positions);
  EXPECT_EQ(all.pairs().size(), Within(cloth, cloth.positions, 1.2f + 0.5f, 0).size());
  EXPECT_FALSE(all.pairs().empty());
}

TEST(SelfContactPairs, HoldEveryPairWithinReachOfAFoldedCloth) {
  const KnitCloth cloth = FoldedStrip(0.6f);
  SelfContactPairs pairs(cloth, 0.9f, 0.5f, 2);
  std::vector<glm::vec3> x = cloth.positions;
  pairs.Update(x);
  const auto exact = Within(cloth, x, 0.9f, 2);
  ASSERT_GT(exact.size(), 40u);
  std::set<std::pair<uint32_t, uint32_t>> found;
  for (const PointTriangle& pair : pairs.pairs()) found.emplace(pair.point, pair.triangle);
  for (const auto& pair : exact) EXPECT_TRUE(found.count(pair)) << pair.first << " " << pair.second;
  // Nothing beyond reach + skin.
  for (const auto& pair : found) EXPECT_TRUE(Within(cloth, x, 1.4f, 2).count(pair));

  // Moving every point less than skin / 2 keeps the pairs; the superset still
  // holds every pair within reach.
  for (int j = 6; j < 12; ++j) {
    for (int i = 0; i < 5; ++i) x[cloth.Index(i, j)].z -= 0.24f;
  }
  pairs.Update(x);
  EXPECT_EQ(pairs.searches(), 1);
  found.clear();
  for (const PointTriangle& pair : pairs.pairs()) found.emplace(pair.point, pair.triangle);
  for (const auto& pair : Within(cloth, x, 0.9f, 2)) EXPECT_TRUE(found.count(pair));
  // Moving one further searches again.
  x[0].z += 0.3f;
  pairs.Update(x);
  EXPECT_EQ(pairs.searches(), 2);
}

TEST(SelfContactPairs, RefusesBadParametersAndPositions) {
  const KnitCloth cloth = FoldedStrip(0.6f);
  EXPECT_THROW(SelfContactPairs(cloth, 0.0f, 0.5f, 2), Error);
  EXPECT_THROW(SelfContactPairs(cloth, 0.9f, 0.5f, -1), Error);
  SelfContactPairs pairs(cloth, 0.9f, 0.5f, 2);
  EXPECT_THROW(pairs.Update({glm::vec3(0)}), Error);
}

}  // namespace
}  // namespace loom::animate
