// core/shaders/hemisphere_map.glsl must agree with core/acquire/hemisphere_directions.cpp:
// the renderer looks views up in a table that acquisition laid out with the C++ map.

#include <gtest/gtest.h>

#include "core/acquire/hemisphere_directions.h"
#include "core/gl/egl_context.h"
#include "tests/core/gl/fullscreen_pass.h"

namespace loom::gl {
namespace {

constexpr int kSize = 64;

TEST(HemisphereMapGlsl, ForwardMapMatchesCpp) {
  const auto context = EglContext::Create();
  const Image image = RunFullscreenPass(R"(#version 450 core
#include "hemisphere_map.glsl"
layout(location = 0) out vec4 o;
void main() { o = vec4(SquareToHemisphere(gl_FragCoord.xy / 64.0), 0.0); }
)", kSize, kSize);
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      const int row = kSize - 1 - y;  // images are top row first; gl_FragCoord counts from the bottom
      const glm::vec3 expected = SquareToHemisphere(glm::vec2((x + 0.5f) / kSize, (row + 0.5f) / kSize));
      for (int c = 0; c < 3; ++c) ASSERT_NEAR(image.at(x, y, c), expected[c], 2e-6f) << x << "," << row;
    }
  }
}

TEST(HemisphereMapGlsl, InverseMapMatchesCppAndRoundTrips) {
  const auto context = EglContext::Create();
  const Image image = RunFullscreenPass(R"(#version 450 core
#include "hemisphere_map.glsl"
layout(location = 0) out vec4 o;
void main() {
  vec3 d = SquareToHemisphere(gl_FragCoord.xy / 64.0);
  o = vec4(HemisphereToSquare(d), HemisphereGridCoordinates(d, 8.0));
}
)", kSize, kSize);
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      const int row = kSize - 1 - y;
      const glm::vec2 square((x + 0.5f) / kSize, (row + 0.5f) / kSize);
      const glm::vec3 d = SquareToHemisphere(square);
      const glm::vec2 cpp = HemisphereToSquare(d);
      const glm::vec2 grid = HemisphereGridCoordinates(d, 8);
      ASSERT_NEAR(image.at(x, y, 0), cpp.x, 1e-5f) << x << "," << row;
      ASSERT_NEAR(image.at(x, y, 1), cpp.y, 1e-5f) << x << "," << row;
      ASSERT_NEAR(image.at(x, y, 2), grid.x, 1e-4f);
      ASSERT_NEAR(image.at(x, y, 3), grid.y, 1e-4f);
      ASSERT_NEAR(image.at(x, y, 0), square.x, 1e-4f);  // round trip
      ASSERT_NEAR(image.at(x, y, 1), square.y, 1e-4f);
    }
  }
}

}  // namespace
}  // namespace loom::gl
