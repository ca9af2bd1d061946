#include "core/render/svbrdf_renderer.h"

#include <gtest/gtest.h>

#include <glm/gtc/constants.hpp>

#include "core/spec/defaults.h"
#include "core/spec/spec_json.h"
#include "core/spec/validate.h"

namespace loom {
namespace {

RenderedFrame RenderJson(const std::string& json) {
  const v1::SceneSpec scene = WithDefaults(ParseSpecJson<v1::SceneSpec>(json, "scene"));
  ValidateOrThrow(scene);
  static const auto context = gl::EglContext::Create();
  static SvbrdfRenderer renderer(*context);
  return renderer.Render(scene, BuildSceneGeometry(scene, FileMeshResolver(".")));
}

// A 2 x 2 plane seen straight down by an orthographic camera that frames it exactly.
std::string PlaneScene(const std::string& extra_objects, const std::string& lights, int msaa = 1) {
  return R"({"objects": [{"mesh": {"builtin": "BUILTIN_SHAPE_PLANE"},
      "transform": {"scale": {"x": 2, "y": 2, "z": 1}}, "base_colour": {"r": 0.6, "g": 0.3, "b": 0.15}})" +
         extra_objects + R"(],
    "camera": {"projection": "PROJECTION_ORTHOGRAPHIC", "ortho_height": 2, "position": {"x": 0, "y": 0, "z": 5},
               "up": {"x": 0, "y": 1, "z": 0}, "near": 0.1, "far": 10},
    "lights": [)" + lights + R"(],
    "render": {"width": 64, "height": 64, "msaa_samples": )" + std::to_string(msaa) + "}}";
}

TEST(SvbrdfRenderer, LambertianPlaneUnderAZenithLightIsAlbedoOverPiTimesIrradiance) {
  const RenderedFrame frame = RenderJson(PlaneScene("",
      R"({"type": "LIGHT_TYPE_DIRECTIONAL", "direction": {"x": 0, "y": 0, "z": 1}, "intensity": 2.5})"));
  const glm::vec3 albedo(0.6f, 0.3f, 0.15f);
  for (int y = 0; y < 64; y += 7) {
    for (int x = 0; x < 64; x += 7) {
      for (int c = 0; c < 3; ++c) {
        ASSERT_NEAR(frame.image.at(x, y, c), albedo[c] / glm::pi<float>() * 2.5f, 1e-5f) << x << "," << y;
      }
    }
  }
  EXPECT_GT(frame.gpu_ms, 0.0);  // the timer query ran
}

TEST(SvbrdfRenderer, ObliqueLightFollowsTheCosine) {
  // 60° from the normal: cos = 0.5.
  const RenderedFrame frame = RenderJson(PlaneScene("",
      R"({"direction": {"x": 0.8660254, "y": 0, "z": 0.5}, "intensity": 1})"));
  EXPECT_NEAR(frame.image.at(32, 32, 0), 0.6f / glm::pi<float>() * 0.5f, 1e-5f);
}

TEST(SvbrdfRenderer, PointLightFallsOffWithTheSquareOfDistance) {
  const RenderedFrame frame = RenderJson(PlaneScene("",
      R"({"type": "LIGHT_TYPE_POINT", "position": {"x": 0, "y": 0, "z": 2}, "intensity": 8})"));
  // Below the light (pixel centre (31.5, 31.5) is 1/64 off the axis: within 1e-3 relative).
  EXPECT_NEAR(frame.image.at(32, 32, 0), 0.6f / glm::pi<float>() * 8.0f / 4.0f, 1e-3f);
  // At the plane's corner (≈(0.98, 0.98)): d² = 4 + 2·0.98², cos = 2/d.
  const float d2 = 4.0f + 2.0f * 0.984375f * 0.984375f;
  EXPECT_NEAR(frame.image.at(63, 0, 0), 0.6f / glm::pi<float>() * 8.0f / d2 * (2.0f / std::sqrt(d2)), 1e-4f);
}

TEST(SvbrdfRenderer, ASphereShadowsThePlaneBelowIt) {
  const std::string sphere = R"(, {"mesh": {"builtin": "BUILTIN_SHAPE_SPHERE"},
      "transform": {"translation": {"x": 0.5, "y": 0.5, "z": 1}, "scale": {"x": 0.2, "y": 0.2, "z": 0.2}}})";
  // Light from 14° off the zenith towards -x: the sphere at (0.5, 0.5, 1) shadows the
  // plane around (0.75, 0.5).
  const RenderedFrame steep = RenderJson(PlaneScene(sphere,
      R"({"direction": {"x": -0.25, "y": 0, "z": 1}, "intensity": 1, "casts_shadows": true})"));
  // Shadow centre: (0.5 + 0.25, 0.5) on the plane → pixel ((0.75+1)/2·64, (1−(0.5+1)/2)·64) = (56, 16).
  const float lit = 0.6f / glm::pi<float>() * glm::dot(glm::normalize(glm::vec3(-0.25f, 0, 1)), glm::vec3(0, 0, 1));
  EXPECT_NEAR(steep.image.at(56, 16, 0), 0.0f, 1e-4f);  // in the shadow (no ambient)
  EXPECT_NEAR(steep.image.at(10, 50, 0), lit, 1e-4f);   // far from it
  // Without casts_shadows the same spot is lit.
  const RenderedFrame unshadowed = RenderJson(PlaneScene(sphere,
      R"({"direction": {"x": -0.25, "y": 0, "z": 1}, "intensity": 1, "casts_shadows": false})"));
  EXPECT_NEAR(unshadowed.image.at(56, 16, 0), lit, 1e-4f);
}

TEST(SvbrdfRenderer, MsaaAveragesEdgesAgainstTheBackground) {
  const std::string scene = R"({"objects": [{"mesh": {"builtin": "BUILTIN_SHAPE_PLANE"}, "base_colour": {"r": 1, "g": 1, "b": 1}}],
    "camera": {"projection": "PROJECTION_ORTHOGRAPHIC", "ortho_height": 2, "position": {"x": 0.01, "y": 0.013, "z": 5},
               "target": {"x": 0.01, "y": 0.013, "z": 0}, "up": {"x": 0.3, "y": 1, "z": 0}},
    "ambient": {"r": 1, "g": 1, "b": 1},
    "render": {"width": 64, "height": 64, "msaa_samples": 4}})";
  const RenderedFrame frame = RenderJson(scene);
  // A unit plane, rotated in view, covers part of the frame: some edge pixels are partial.
  int partial = 0;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      const float v = frame.image.at(x, y, 0);
      if (v > 0.01f && v < 0.99f) ++partial;
    }
  EXPECT_GT(partial, 20);
}

}  // namespace
}  // namespace loom
