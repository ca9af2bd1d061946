#include "core/animate/motion.h"

#include <gtest/gtest.h>

namespace loom::animate {
namespace {

TEST(Motion, LegsMoveBetweenTheirTimesAndAdd) {
  Motion motion(glm::vec3(1, 0, 0), 1.0, 3.0);
  motion.legs.push_back({glm::vec3(0, 2, 0), 2.0, 4.0});
  EXPECT_EQ(motion.Displacement(0.5), glm::vec3(0));
  EXPECT_EQ(motion.Displacement(2.5), glm::vec3(1.5f, 1.0f, 0));
  EXPECT_EQ(motion.Displacement(10.0), glm::vec3(2, 4, 0));
  EXPECT_EQ(motion.Velocity(2.5), glm::vec3(1, 2, 0));
  EXPECT_EQ(motion.Velocity(3.0), glm::vec3(0, 2, 0));  // a leg stops at its end
  EXPECT_EQ(motion.Velocity(4.0), glm::vec3(0));
  EXPECT_TRUE(motion.valid());
  motion.legs.push_back({glm::vec3(1), 5.0, 4.0});
  EXPECT_FALSE(motion.valid());
}

}  // namespace
}  // namespace loom::animate
