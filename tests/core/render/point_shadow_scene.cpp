#include "tests/core/render/point_shadow_scene.h"

#include <algorithm>
#include <cmath>
#include <gtest/gtest.h>

#include <glm/glm.hpp>
#include <glm/gtc/constants.hpp>

namespace loom::testing {
namespace {

constexpr int kSize = 64;
const glm::vec3 kLight(-0.5f, 0.5f, 1.0f);
constexpr float kIntensity = 2.0f;
const glm::vec3 kSphere(0.1f, 0.5f, 0.5f);
constexpr float kRadius = 0.2f;
constexpr float kAlbedo = 0.6f;  // red
constexpr float kEdge = 0.03f;   // world units kept clear of the shadow's edge

}  // namespace

std::string PointShadowSceneJson(bool casts_shadows, const std::string& method) {
  return R"({"objects": [{"mesh": {"builtin": "BUILTIN_SHAPE_PLANE"},
      "transform": {"scale": {"x": 2, "y": 2, "z": 1}}, "base_colour": {"r": 0.6, "g": 0.3, "b": 0.15}},
      {"mesh": {"builtin": "BUILTIN_SHAPE_SPHERE"},
       "transform": {"translation": {"x": 0.1, "y": 0.5, "z": 0.5}, "scale": {"x": 0.2, "y": 0.2, "z": 0.2}}}],
    "camera": {"projection": "PROJECTION_ORTHOGRAPHIC", "ortho_height": 2, "position": {"x": 0, "y": 0, "z": 5},
               "up": {"x": 0, "y": 1, "z": 0}, "near": 0.1, "far": 10},
    "lights": [{"type": "LIGHT_TYPE_POINT", "position": {"x": -0.5, "y": 0.5, "z": 1}, "intensity": 2,
                "casts_shadows": )" +
         std::string(casts_shadows ? "true" : "false") + R"(}],
    "render": {"method": ")" + method + R"(", "width": 64, "height": 64, "msaa_samples": 1, "reference_samples": 4}})";
}

PointShadowCheck CheckPointShadow(const Image& image) {
  PointShadowCheck check;
  for (int py = 0; py < kSize; ++py) {
    for (int px = 0; px < kSize; ++px) {
      const glm::vec3 p((px + 0.5f) / 32.0f - 1.0f, 1.0f - (py + 0.5f) / 32.0f, 0.0f);
      if (glm::length(glm::vec2(p) - glm::vec2(kSphere)) < kRadius + kEdge) continue;  // the sphere seen from above
      const glm::vec3 to_light = kLight - p;
      const float s = std::clamp(glm::dot(kSphere - p, to_light) / glm::dot(to_light, to_light), 0.0f, 1.0f);
      const float miss = glm::length(p + s * to_light - kSphere);
      const float red = image.at(px, py, 0);
      if (miss < kRadius - kEdge) {
        ++check.inside;
        if (p.x > 0.5f + kEdge) ++check.inside_plus_x_face;
        if (red < 1e-4f) ++check.dark_inside;
      } else if (miss > kRadius + kEdge) {
        ++check.outside;
        const float d = glm::length(to_light);
        const float lambert = kAlbedo / glm::pi<float>() * kIntensity * (to_light.z / d) / (d * d);
        check.worst_outside = std::max(check.worst_outside, static_cast<double>(std::abs(red - lambert) / lambert));
      }
    }
  }
  return check;
}

void ExpectShadowWhereTheRaysMeetTheSphere(const std::function<Image(const std::string& json)>& render,
                                           const std::string& method, double lit_tolerance) {
  const PointShadowCheck shadowed = CheckPointShadow(render(PointShadowSceneJson(true, method)));
  EXPECT_GT(shadowed.inside, 200);
  EXPECT_GT(shadowed.inside_plus_x_face, 50);
  EXPECT_EQ(shadowed.dark_inside, shadowed.inside);
  EXPECT_GT(shadowed.outside, 2000);
  EXPECT_LT(shadowed.worst_outside, lit_tolerance);
  EXPECT_EQ(CheckPointShadow(render(PointShadowSceneJson(false, method))).dark_inside, 0);
}

}  // namespace loom::testing
