#include "core/render/test_scene.h"

#include <gtest/gtest.h>

#include <cmath>

namespace loom {
namespace {

// Figures of the test scene that only hold if depth, shading, uvs and MSAA all work.
TEST(TestScene, ShowsALitSphereOnAFloorAgainstTheClearColour) {
  const auto context = gl::EglContext::Create();
  TestSceneOptions options;
  options.width = 160;
  options.height = 120;
  const Image image = RenderTestScene(*context, options);
  ASSERT_EQ(image.width, 160);
  ASSERT_EQ(image.height, 120);

  // Top-left corner is sky: exactly the clear colour.
  EXPECT_FLOAT_EQ(image.at(0, 0, 0), 0.02f);
  EXPECT_FLOAT_EQ(image.at(0, 0, 1), 0.025f);
  EXPECT_FLOAT_EQ(image.at(0, 0, 2), 0.03f);

  // The sphere fills the centre: red or yellow stripes, red channel dominant.
  const float r = image.at(80, 50, 0), g = image.at(80, 50, 1), b = image.at(80, 50, 2);
  EXPECT_GT(r, b * 2.0f) << r << " " << g << " " << b;

  // Every value finite and non-negative; the sphere's lit side is brighter than its shadowed side.
  for (float v : image.pixels) ASSERT_TRUE(std::isfinite(v) && v >= 0.0f);
  float lit = 0.0f, unlit = 0.0f;
  for (int y = 40; y < 60; ++y) {
    lit += image.at(70, y, 0) + image.at(70, y, 1);
    unlit += image.at(95, y, 0) + image.at(95, y, 1);
  }
  EXPECT_GT(lit, unlit);
}

}  // namespace
}  // namespace loom
