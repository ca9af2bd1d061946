#include "lab/pareto_front.h"

#include <gtest/gtest.h>

#include <cmath>

namespace loom::lab {
namespace {

TEST(ParetoFront, KeepsOnlyPointsNothingBeatsOnBothAxes) {
  // 0 and 3 are dominated by 1 (cheaper and better); 4 costs the most but is best.
  const std::vector<CostError> points = {{2.0, 5.0}, {1.0, 4.0}, {3.0, 2.0}, {4.0, 3.0}, {5.0, 1.0}};
  EXPECT_EQ(ParetoFront(points), (std::vector<size_t>{1, 2, 4}));
}

TEST(ParetoFront, OrdersByCostAndDropsEqualCostWithMoreError) {
  const std::vector<CostError> points = {{3.0, 1.0}, {1.0, 2.0}, {1.0, 3.0}};
  EXPECT_EQ(ParetoFront(points), (std::vector<size_t>{1, 0}));
}

TEST(ParetoFront, KeepsTheFirstOfIdenticalPoints) {
  const std::vector<CostError> points = {{1.0, 1.0}, {1.0, 1.0}};
  EXPECT_EQ(ParetoFront(points), (std::vector<size_t>{0}));
}

TEST(ParetoFront, LeavesOutNonFiniteFigures) {
  const std::vector<CostError> points = {{NAN, 0.0}, {1.0, INFINITY}, {2.0, 1.0}};
  EXPECT_EQ(ParetoFront(points), (std::vector<size_t>{2}));
  EXPECT_TRUE(ParetoFront({}).empty());
}

}  // namespace
}  // namespace loom::lab
