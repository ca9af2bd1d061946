// The headless GL path end to end on whatever EGL offers (llvmpipe in CI): context,
// shaders, a float framebuffer and read-back, checked pixel by pixel.

#include "core/gl/egl_context.h"

#include <gtest/gtest.h>

#include <string>

#include "core/gl/framebuffer.h"
#include "core/gl/mesh_buffer.h"
#include "core/gl/shader_program.h"
#include "core/util/error.h"

namespace loom::gl {
namespace {

constexpr const char* kFlatVertex = R"(#version 450 core
layout(location = 0) in vec3 a_position;
void main() { gl_Position = vec4(a_position, 1.0); }
)";

constexpr const char* kFlatFragment = R"(#version 450 core
uniform vec4 u_colour;
layout(location = 0) out vec4 o_colour;
void main() { o_colour = u_colour; }
)";

TEST(EglContext, ReportsAnOpenGl45CoreDevice) {
  const auto context = EglContext::Create();
  const DeviceInfo& info = context->info();
  EXPECT_FALSE(info.gl_renderer.empty());
  EXPECT_FALSE(info.gl_vendor.empty());
  EXPECT_TRUE(info.platform == "device" || info.platform == "surfaceless") << info.platform;
  GLint major = 0, minor = 0, profile = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &major);
  glGetIntegerv(GL_MINOR_VERSION, &minor);
  glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
  EXPECT_GE(major * 10 + minor, 45) << info.gl_version;
  EXPECT_TRUE(profile & GL_CONTEXT_CORE_PROFILE_BIT);
  std::printf("renderer: %s | %s\n", info.gl_renderer.c_str(), info.gl_version.c_str());
}

// Draws the right triangle (-1,-1), (1,-1), (-1,1) — the lower-left half of the
// target — in `colour` over `clear`, and reads the target back.
Image DrawLowerLeftTriangle(int size, int samples, const glm::vec4& clear, const glm::vec4& colour) {
  Framebuffer target(size, size, samples);
  ShaderProgram program = ShaderProgram::Link({{GL_VERTEX_SHADER, "flat.vert", kFlatVertex},
                                               {GL_FRAGMENT_SHADER, "flat.frag", kFlatFragment}});
  TriangleMesh triangle;
  triangle.positions = {{-1.0f, -1.0f, 0.0f}, {1.0f, -1.0f, 0.0f}, {-1.0f, 1.0f, 0.0f}};
  triangle.indices = {0, 1, 2};
  MeshBuffer mesh(triangle);
  target.Bind();
  glClearColor(clear.r, clear.g, clear.b, clear.a);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  program.Use();
  program.Set("u_colour", colour);
  mesh.Draw();
  return target.ReadPixels();
}

// On a 16 x 16 float target, in a colour that is not representable in 8 bits:
// covered pixels must read back the exact float, uncovered ones the exact clear value.
TEST(EglContext, DrawsAKnownTriangleIntoAFloatFramebuffer) {
  const auto context = EglContext::Create();
  constexpr int kSize = 16;
  const glm::vec4 clear(0.125f, 0.0f, 2.5f, 0.0f);  // > 1: the target really is float
  const glm::vec4 colour(0.1234567f, 7.5f, -0.25f, 1.0f);
  const Image image = DrawLowerLeftTriangle(kSize, 1, clear, colour);

  ASSERT_EQ(image.width, kSize);
  ASSERT_EQ(image.height, kSize);
  int covered = 0, uncovered = 0;
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      // GL pixel (x, row) with row counted from the bottom; the hypotenuse is
      // x + row = kSize - 1 at pixel centres, where coverage follows tie rules.
      const int row = kSize - 1 - y;
      if (x + row == kSize - 1) continue;
      const bool inside = x + row < kSize - 1;
      const glm::vec4 expected = inside ? colour : clear;
      for (int c = 0; c < 4; ++c) {
        ASSERT_EQ(image.at(x, y, c), expected[c]) << "pixel (" << x << ", " << y << ") channel " << c;
      }
      (inside ? covered : uncovered)++;
    }
  }
  EXPECT_EQ(covered, kSize * (kSize - 1) / 2);
  EXPECT_EQ(uncovered, kSize * (kSize - 1) / 2);
}

TEST(EglContext, MultisampledTargetResolvesEdgesToPartialCoverage) {
  const auto context = EglContext::Create();
  const Image image = DrawLowerLeftTriangle(8, 4, glm::vec4(0.0f), glm::vec4(1.0f));
  // Pixels on the diagonal are cut by the edge: resolved coverage strictly between 0 and 1.
  for (int x = 0; x < 8; ++x) {
    const float value = image.at(x, x, 0);  // top-left to bottom-right is the hypotenuse
    EXPECT_GT(value, 0.0f) << "x = " << x;
    EXPECT_LT(value, 1.0f) << "x = " << x;
  }
  EXPECT_EQ(image.at(0, 7, 0), 1.0f);  // bottom-left corner: inside
  EXPECT_EQ(image.at(7, 0, 0), 0.0f);  // top-right corner: outside
}

TEST(EglContext, SoftwareOnlyPicksAMesaSoftwareRenderer) {
  ContextOptions options = DefaultContextOptions();
  options.software_only = true;
  const auto context = EglContext::Create(options);
  EXPECT_TRUE(context->info().software) << context->info().gl_renderer;
}

// One worker per GPU: a context pinned to the device the default picked is made on
// that device; an index EGL does not list is a clear error naming the ones it does.
TEST(EglContext, APinnedDeviceIsTheOneUsed) {
  const auto best = EglContext::Create();
  if (best->info().device_index < 0) GTEST_SKIP() << "no EGL device platform here (surfaceless context)";
  ContextOptions options = DefaultContextOptions();
  options.device_index = best->info().device_index;
  const auto pinned = EglContext::Create(options);
  EXPECT_EQ(pinned->info().device_index, best->info().device_index);
  EXPECT_EQ(pinned->info().gl_renderer, best->info().gl_renderer);
}

TEST(EglContext, ADeviceIndexEglDoesNotListIsAClearError) {
  ContextOptions options = DefaultContextOptions();
  options.device_index = 1000;
  try {
    EglContext::Create(options);
    FAIL() << "device 1000 made a context";
  } catch (const Error& error) {
    EXPECT_EQ(error.code(), ErrorCode::kInvalidArgument);
    EXPECT_NE(std::string(error.what()).find("GL device 1000 does not exist: EGL lists"), std::string::npos)
        << error.what();
  }
}

}  // namespace
}  // namespace loom::gl
