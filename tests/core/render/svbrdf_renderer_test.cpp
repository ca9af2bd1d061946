#include "core/render/gpu_renderer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>
#include <glm/gtc/constants.hpp>

#include "core/acquire/hemisphere_directions.h"
#include "core/gl/framebuffer.h"
#include "core/render/fabric_textures.h"

#include "core/spec/defaults.h"
#include "core/spec/spec_json.h"
#include "core/spec/validate.h"
#include "tests/core/render/image_probes.h"
#include "tests/core/render/point_shadow_scene.h"

namespace loom {
namespace {

RenderedFrame RenderJson(const std::string& json) {
  const v1::SceneSpec scene = WithDefaults(ParseSpecJson<v1::SceneSpec>(json, "scene"));
  ValidateOrThrow(scene);
  static const auto context = gl::EglContext::Create();
  static GpuRenderer renderer(*context);
  return renderer.Render(scene, BuildSceneGeometry(scene, FileMeshResolver(".")), {});
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

TEST(GpuRenderer, LambertianPlaneUnderAZenithLightIsAlbedoOverPiTimesIrradiance) {
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

// The renderer keeps its target between frames of one size: a second frame into it
// is cleared and drawn alike, and timed.
TEST(GpuRenderer, ASecondFrameIntoTheKeptTargetIsTheSameAndTimed) {
  const std::string scene = PlaneScene("", R"({"direction": {"x": 0.3, "y": 0.2, "z": 1}, "intensity": 2})");
  const RenderedFrame first = RenderJson(scene);
  const RenderedFrame second = RenderJson(scene);
  EXPECT_GT(first.gpu_ms, 0.0);
  EXPECT_GT(second.gpu_ms, 0.0);
  EXPECT_EQ(first.image.pixels, second.image.pixels);
}

TEST(GpuRenderer, ObliqueLightFollowsTheCosine) {
  // 60° from the normal: cos = 0.5.
  const RenderedFrame frame = RenderJson(PlaneScene("",
      R"({"direction": {"x": 0.8660254, "y": 0, "z": 0.5}, "intensity": 1})"));
  EXPECT_NEAR(frame.image.at(32, 32, 0), 0.6f / glm::pi<float>() * 0.5f, 1e-5f);
}

TEST(GpuRenderer, PointLightFallsOffWithTheSquareOfDistance) {
  const RenderedFrame frame = RenderJson(PlaneScene("",
      R"({"type": "LIGHT_TYPE_POINT", "position": {"x": 0, "y": 0, "z": 2}, "intensity": 8})"));
  // Below the light (pixel centre (31.5, 31.5) is 1/64 off the axis: within 1e-3 relative).
  EXPECT_NEAR(frame.image.at(32, 32, 0), 0.6f / glm::pi<float>() * 8.0f / 4.0f, 1e-3f);
  // At the plane's corner (≈(0.98, 0.98)): d² = 4 + 2·0.98², cos = 2/d.
  const float d2 = 4.0f + 2.0f * 0.984375f * 0.984375f;
  EXPECT_NEAR(frame.image.at(63, 0, 0), 0.6f / glm::pi<float>() * 8.0f / d2 * (2.0f / std::sqrt(d2)), 1e-4f);
}

TEST(GpuRenderer, ASphereShadowsThePlaneBelowIt) {
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

// A point light's shadow (six cube faces) falls where the rays to the light meet the
// sphere, across the seam of two faces; without casts_shadows there is none.
TEST(GpuRenderer, APointLightsShadowFallsWhereItsRaysMeetTheSphere) {
  testing::ExpectShadowWhereTheRaysMeetTheSphere([](const std::string& json) { return RenderJson(json).image; },
                                                 "RENDER_METHOD_SVBRDF", 1e-3);
}

TEST(GpuRenderer, MsaaAveragesEdgesAgainstTheBackground) {
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

TEST(GpuRenderer, MsaaBeyondTheGlLimitRendersAtTheLimit) {
  // Validation allows 16 samples (a GPU's count); llvmpipe's float target stops at
  // 4, where 8 or 16 used to leave the framebuffer incomplete and the render failed.
  const auto scene = [](int msaa) {
    return PlaneScene(R"(, {"mesh": {"builtin": "BUILTIN_SHAPE_SPHERE"},
        "transform": {"translation": {"x": 0.2, "y": 0.1, "z": 0.6}, "scale": {"x": 0.3, "y": 0.3, "z": 0.3}}})",
                      R"({"direction": {"x": 0.3, "y": 0.2, "z": 1}, "intensity": 1})", msaa);
  };
  const RenderedFrame beyond = RenderJson(scene(16));
  const int limit = gl::Framebuffer::MaxSamples();  // the renderer's context is current
  ASSERT_GE(limit, 1);
  if (limit >= 16) GTEST_SKIP() << "this GL supports 16 samples: nothing beyond its limit to test";
  const RenderedFrame at_limit = RenderJson(scene(limit));
  EXPECT_EQ(beyond.image.pixels, at_limit.image.pixels);
}

}  // namespace
}  // namespace loom

namespace loom {
namespace {

// A fabric whose every texel is diffuse with albedo `albedo`, frame = the tile
// frame, T = 1, alpha = 1, on every level of a `resolution` array with a k×k LUT.
FabricTextureData DiffuseFabric(uint32_t resolution, uint32_t view_side, glm::vec3 albedo) {
  FabricTextureData data;
  uint32_t levels = 0;
  while ((resolution >> levels) > 0) ++levels;
  data.Allocate(resolution, 0, view_side, levels);
  for (uint32_t level = 0; level < levels; ++level) {
    const uint32_t r = data.LevelResolution(level);
    for (uint32_t y = 0; y < r; ++y)
      for (uint32_t x = 0; x < r; ++x) {
        data.Param(level, 0, x, y) = glm::vec4(albedo / glm::pi<float>(), 0.0f);
        data.Param(level, 1, x, y) = glm::vec4(0, 0, 1, 0);
        data.Param(level, 2, x, y) = glm::vec4(1, 0, 0, 0);
        for (uint32_t view = 0; view < view_side * view_side; ++view) data.Lut(level, x, y, view) = glm::vec4(1.0f);
      }
  }
  return data;
}

// The plane of PlaneScene as cloth with `repeat` tiles, optionally over a red plane,
// seen `tilt_degrees` off the normal (the camera moves towards −y). Nearest texels,
// so that a pixel shows the one texel the tests probe.
std::string ClothScene(float repeat, bool red_floor, int msaa, const char* level_mode = "LEVEL_MODE_TRILINEAR",
                       float tilt_degrees = 0.0f, float lod_bias = 0.0f,
                       const char* shading_rate = "SHADING_RATE_PIXEL") {
  const float tilt = glm::radians(tilt_degrees);
  const std::string floor = red_floor ? R"(, {"mesh": {"builtin": "BUILTIN_SHAPE_PLANE"},
      "transform": {"translation": {"z": -0.5}, "scale": {"x": 4, "y": 4, "z": 1}}, "base_colour": {"r": 1, "g": 0, "b": 0}})"
                                      : "";
  const std::string r = std::to_string(repeat);
  return R"({"objects": [{"mesh": {"builtin": "BUILTIN_SHAPE_PLANE"}, "transform": {"scale": {"x": 2, "y": 2, "z": 1}},
      "fabric": {"fabric": {"knit": {}}, "repeat_u": )" + r + R"(, "repeat_v": )" + r + "}}" + floor + R"(],
    "camera": {"projection": "PROJECTION_ORTHOGRAPHIC", "ortho_height": 2, "position": {"x": 0, "y": )" +
         std::to_string(-5.0f * std::sin(tilt)) + R"(, "z": )" + std::to_string(5.0f * std::cos(tilt)) + R"(},
               "up": {"x": 0, "y": 1, "z": 0}, "near": 0.1, "far": 10},
    "lights": [{"direction": {"x": 0, "y": 0, "z": 1}, "intensity": 2}],
    "render": {"width": 64, "height": 64, "msaa_samples": )" + std::to_string(msaa) +
         R"(, "level_mode": ")" + level_mode + R"(", "texel_filter": "TEXEL_FILTER_NEAREST", "lod_bias": )" +
         std::to_string(lod_bias) + R"(, "shading_rate": ")" + shading_rate + R"("}})";
}

// The scene with `data` as the fabric of every object that has one.
RenderedFrame RenderCloth(const std::string& json, const FabricTextureData& data) {
  const v1::SceneSpec scene = WithDefaults(ParseSpecJson<v1::SceneSpec>(json, "scene"));
  ValidateOrThrow(scene);
  static const auto context = gl::EglContext::Create();
  static GpuRenderer renderer(*context);
  const auto meshes = BuildSceneGeometry(scene, FileMeshResolver("."));
  FabricTextures textures(data, /*half=*/false);
  std::vector<const GpuFabric*> fabrics(meshes.size(), nullptr);
  for (size_t i = 0; i < meshes.size(); ++i) {
    if (meshes[i].object->has_fabric()) fabrics[i] = &textures;
  }
  return renderer.Render(scene, meshes, fabrics);
}

// A white fabric of coverage `a` from every direction, on every level.
FabricTextureData CoveringFabric(float a) {
  FabricTextureData data = DiffuseFabric(8, 3, glm::vec3(1.0f));
  for (uint32_t level = 0; level < data.levels(); ++level)
    for (uint32_t y = 0; y < data.LevelResolution(level); ++y)
      for (uint32_t x = 0; x < data.LevelResolution(level); ++x)
        for (uint32_t view = 0; view < 9; ++view) data.Lut(level, x, y, view).a = a;
  return data;
}

TEST(SvbrdfFabric, DiffuseFabricMatchesLambertExactly) {
  const glm::vec3 albedo(0.5f, 0.25f, 0.125f);
  const RenderedFrame frame = RenderCloth(ClothScene(4, false, 1), DiffuseFabric(8, 3, albedo));
  for (int y = 1; y < 64; y += 9)
    for (int x = 1; x < 64; x += 9)
      for (int c = 0; c < 3; ++c) ASSERT_NEAR(frame.image.at(x, y, c), albedo[c] / glm::pi<float>() * 2.0f, 1e-5f);
}

TEST(SvbrdfFabric, LookupTableScalesByTheViewsEntry) {
  // k = 3 puts a stored view exactly at the zenith (index 4), where this camera looks from.
  FabricTextureData data = DiffuseFabric(8, 3, glm::vec3(0.5f));
  for (uint32_t level = 0; level < data.levels(); ++level)
    for (uint32_t y = 0; y < data.LevelResolution(level); ++y)
      for (uint32_t x = 0; x < data.LevelResolution(level); ++x) data.Lut(level, x, y, 4) = glm::vec4(0.5f, 1.0f, 1.5f, 1.0f);
  const RenderedFrame frame = RenderCloth(ClothScene(4, false, 1), data);
  const float base = 0.5f / glm::pi<float>() * 2.0f;
  EXPECT_NEAR(frame.image.at(20, 30, 0), 0.5f * base, 1e-5f);
  EXPECT_NEAR(frame.image.at(20, 30, 1), 1.0f * base, 1e-5f);
  EXPECT_NEAR(frame.image.at(20, 30, 2), 1.5f * base, 1e-5f);
}

TEST(SvbrdfFabric, HolesShowTheRedPlaneBehind) {
  // A white fabric whose texel (0, 0) of a 2×2 array is a hole from every view.
  FabricTextureData data = DiffuseFabric(2, 3, glm::vec3(1.0f));
  for (uint32_t view = 0; view < 9; ++view) data.Lut(0, 0, 0, view).a = 0.0f;
  for (int msaa : {1, 4}) {
    const RenderedFrame frame = RenderCloth(ClothScene(2, true, msaa, "LEVEL_MODE_NONE"), data);
    // Two tiles across 64 px: texel (0,0) of the first tile covers pixels x 0–15 and
    // image rows 48–63 (tile y grows upwards).
    const float white = 1.0f / glm::pi<float>() * 2.0f;
    EXPECT_NEAR(frame.image.at(8, 56, 0), 1.0f / glm::pi<float>() * 2.0f, 1e-5f) << msaa;  // red floor, lit
    EXPECT_NEAR(frame.image.at(8, 56, 1), 0.0f, 1e-6f) << msaa;
    EXPECT_NEAR(frame.image.at(24, 56, 1), white, 1e-5f) << msaa;  // texel (1, 0): cloth
    EXPECT_NEAR(frame.image.at(8, 40, 1), white, 1e-5f) << msaa;   // texel (0, 1): cloth
  }
}

// Cloth casts shadows through its holes: with coverage alpha a from every
// direction, a shadow-casting light straight above reaches the red floor below at
// 1 − a of its irradiance (shadow_cloth.frag dithers depth writes in 1/16 steps;
// the lights' PCF averages them). Seen head-on through the same cloth, a pixel's
// green is the white cloth's a · 2/π, its red that plus (1 − a) times the floor's
// 2/π · visibility. (Until cloth wrote coverage into the map the floor was black.)
TEST(SvbrdfFabric, ClothLetsLightThroughItsHolesOntoTheFloor) {
  std::string scene = ClothScene(4, true, 1, "LEVEL_MODE_TRILINEAR");
  const std::string light = R"("intensity": 2})";
  scene.replace(scene.find(light), light.size(), R"("intensity": 2, "casts_shadows": true})");
  for (const float a : {0.25f, 0.5f, 0.75f}) {
    const RenderedFrame frame = RenderCloth(scene, CoveringFabric(a));
    const float lit = 2.0f / glm::pi<float>();
    double visibility = 0.0;
    int pixels = 0;
    for (int y = 16; y < 48; ++y)
      for (int x = 16; x < 48; ++x) {
        ASSERT_NEAR(frame.image.at(x, y, 1), a * lit, 1e-4f) << a;
        visibility += (frame.image.at(x, y, 0) - a * lit) / ((1.0f - a) * lit);
        ++pixels;
      }
    EXPECT_NEAR(visibility / pixels, 1.0 - a, 0.01) << "coverage " << a;  // measured within 0.003
  }
}

// Two layers of cloth of coverage ½ (z = 0 and −0.2, x from −1 to 1) under a light
// 45° off the zenith towards −x: on the floor (z = −0.5) their shadows, thrown 0.5
// and 0.3 to +x, overlap from x = 1 to 1.3, and the upper layer's alone reaches 1.5.
// Light through both layers is ¼ (independent holes; measured 0.26 over the 32
// tiles a side), through one ½. The camera looks straight down at x 1 to 2.
TEST(SvbrdfFabric, TwoLayersOfClothLetThroughTheProductOfTheirHoles) {
  const std::string cloth = R"({"mesh": {"builtin": "BUILTIN_SHAPE_PLANE"},
      "transform": {"translation": {"z": Z}, "scale": {"x": 2, "y": 2, "z": 1}},
      "fabric": {"fabric": {"knit": {}}, "repeat_u": 32, "repeat_v": 32}})";
  const auto at = [&](const char* z) { std::string c = cloth; return c.replace(c.find('Z'), 1, z); };
  const std::string scene = R"({"objects": [)" + at("0") + ", " + at("-0.2") + R"(,
      {"mesh": {"builtin": "BUILTIN_SHAPE_PLANE"}, "transform": {"translation": {"z": -0.5}, "scale": {"x": 8, "y": 8, "z": 1}},
       "base_colour": {"r": 1, "g": 0, "b": 0}}],
    "camera": {"projection": "PROJECTION_ORTHOGRAPHIC", "ortho_height": 1, "position": {"x": 1.5, "y": 0, "z": 5},
               "target": {"x": 1.5, "y": 0, "z": 0}, "up": {"x": 0, "y": 1, "z": 0}, "near": 0.1, "far": 10},
    "lights": [{"direction": {"x": -1, "y": 0, "z": 1}, "intensity": 2, "casts_shadows": true}],
    "render": {"width": 64, "height": 64, "msaa_samples": 1}})";
  const Image image = RenderCloth(scene, CoveringFabric(0.5f)).image;
  // Columns at 64 px a unit from x = 1.
  const double lit = testing::MeanRedInColumns(image, 40, 64);             // x 1.63 to 2: no shadow
  EXPECT_NEAR(testing::MeanRedInColumns(image, 3, 16) / lit, 0.25, 0.03);  // x 1.05 to 1.25: both layers
  EXPECT_NEAR(testing::MeanRedInColumns(image, 22, 30) / lit, 0.5, 0.03);  // x 1.34 to 1.47: the upper only
}

// The same two layers stacked exactly (a zenith light, the same uv under every
// point): each object dithers with its own pattern, so the floor seen head-on
// through both gets (1 − a)² of the light, not the (1 − a) of one pattern shared. A
// pixel's red over its green is the floor's share: (1 − a)² of it shows through the
// white layers, lit at 2/π · (1 − a)².
TEST(SvbrdfFabric, TwoStackedLayersOfClothDoNotShareTheirHoles) {
  // 32 tiles a side: the dither's shift changes per tile, and the overlap of two
  // shifted patterns is 0 or ½ per tile at a = ½, ¼ only over many tiles.
  std::string scene = ClothScene(32, true, 1, "LEVEL_MODE_TRILINEAR");
  const std::string light = R"("intensity": 2})";
  scene.replace(scene.find(light), light.size(), R"("intensity": 2, "casts_shadows": true})");
  const std::string objects = R"({"objects": [)";
  scene.insert(scene.find(objects) + objects.size(), R"({"mesh": {"builtin": "BUILTIN_SHAPE_PLANE"},
      "transform": {"translation": {"z": -0.2}, "scale": {"x": 2, "y": 2, "z": 1}},
      "fabric": {"fabric": {"knit": {}}, "repeat_u": 32, "repeat_v": 32}}, )");
  const Image image = RenderCloth(scene, CoveringFabric(0.5f)).image;
  double excess = 0.0;
  for (int y = 16; y < 48; ++y)
    for (int x = 16; x < 48; ++x) excess += image.at(x, y, 0) - image.at(x, y, 1);
  const double through = excess / (32.0 * 32.0) / (0.25 * 2.0 / glm::pi<double>());
  EXPECT_NEAR(through, 0.25, 0.05);  // measured 0.289; one pattern shared: 0.500
}

// Beyond the outermost stored ring of views alpha rises linearly (in grid
// coordinates) to 1 at the horizon: holes close at grazing (fabric_surface.glsl). A white
// fabric with alpha 0.5 from every stored view, over nothing (black): a pixel shows
// alpha · 2/π. Head-on the view is inside the 3×3 grid's outermost ring (56°); at
// 80° it is 0.73 of the way from that ring to the horizon.
TEST(SvbrdfFabric, AlphaRisesTowardsOneBeyondTheOutermostViewRing) {
  FabricTextureData data = DiffuseFabric(2, 3, glm::vec3(1.0f));
  for (uint32_t level = 0; level < data.levels(); ++level)
    for (uint32_t y = 0; y < data.LevelResolution(level); ++y)
      for (uint32_t x = 0; x < data.LevelResolution(level); ++x)
        for (uint32_t view = 0; view < 9; ++view) data.Lut(level, x, y, view).a = 0.5f;
  const auto alpha = [&](float tilt) {
    return RenderCloth(ClothScene(2, false, 1, "LEVEL_MODE_NONE", tilt), data).image.at(32, 32, 1) /
           (2.0f / glm::pi<float>());
  };
  const float tilt = glm::radians(80.0f);
  const glm::vec2 grid = HemisphereGridCoordinates(glm::vec3(0.0f, -std::sin(tilt), std::cos(tilt)), 3);
  const glm::vec2 beyond = glm::max(-grid, grid - 2.0f);
  const float expected = 0.5f + 0.5f * std::clamp(2.0f * std::max(beyond.x, beyond.y), 0.0f, 1.0f);
  EXPECT_GT(expected, 0.8f);
  EXPECT_NEAR(alpha(0.0f), 0.5f, 1e-4f);
  EXPECT_NEAR(alpha(80.0f), expected, 2e-3f);
}

// A lobe past float's range (2^200 head-on), as fits made before the lobe-peak
// guard held between their sampled directions: it overflowed to Inf, and Inf times
// a zero T(v) (or a shadow, or a covering fragment's 1 − alpha) wrote a NaN pixel —
// the NaN of the sweep's level-0 sphere frames. The shader caps a lobe at 2^64.
TEST(SvbrdfFabric, AnOverflowingLobeNeverMakesANonFinitePixel) {
  FabricTextureData data = DiffuseFabric(2, 3, glm::vec3(0.5f));
  data.lobes = 1;
  for (uint32_t level = 0; level < data.levels(); ++level)
    for (uint32_t y = 0; y < data.LevelResolution(level); ++y)
      for (uint32_t x = 0; x < data.LevelResolution(level); ++x)
        for (uint32_t axis = 0; axis < 3; ++axis) data.Param(level, 3 + axis, x, y) = glm::vec4(2, 2, 2, 200);
  for (uint32_t view = 0; view < 9; ++view) data.Lut(0, 0, 0, view) = glm::vec4(0, 0, 0, 1);  // T = 0 on texel (0, 0)
  for (int msaa : {1, 4}) {
    const Image image = RenderCloth(ClothScene(2, false, msaa, "LEVEL_MODE_NONE"), data).image;
    const auto non_finite = std::count_if(image.pixels.begin(), image.pixels.end(),
                                          [](float value) { return !std::isfinite(value); });
    EXPECT_EQ(non_finite, 0) << msaa;
    EXPECT_EQ(image.at(8, 56, 1), 0.0f) << msaa;                    // texel (0, 0): T = 0 times the lobe
    EXPECT_GE(image.at(24, 56, 1), std::exp2(64.0f)) << msaa;       // texel (1, 0): blown out, finite
  }
}

TEST(SvbrdfFabric, LevelModesPickTheFittedLevel) {
  // Each level a different grey: the image shows which level was used.
  FabricTextureData data = DiffuseFabric(4, 3, glm::vec3(0.0f));
  for (uint32_t level = 0; level < data.levels(); ++level)
    for (uint32_t y = 0; y < data.LevelResolution(level); ++y)
      for (uint32_t x = 0; x < data.LevelResolution(level); ++x)
        data.Param(level, 0, x, y) = glm::vec4(glm::vec3(0.1f * (level + 1)), 0.0f);
  // ρ itself is the grey: radiance = ρ · E with E = 2 from the zenith.
  const auto grey = [](const RenderedFrame& frame) { return frame.image.at(30, 30, 0) / 2.0f; };
  // 64 tiles over 64 px at 4 texels a tile: 4 level-0 texels a pixel, λ = 2.
  EXPECT_NEAR(grey(RenderCloth(ClothScene(64, false, 1, "LEVEL_MODE_NEAREST"), data)), 0.3f, 1e-5f);
  EXPECT_NEAR(grey(RenderCloth(ClothScene(64, false, 1, "LEVEL_MODE_NONE"), data)), 0.1f, 1e-5f);
  // 16 tiles: one texel a pixel, λ = 0.
  EXPECT_NEAR(grey(RenderCloth(ClothScene(16, false, 1, "LEVEL_MODE_NEAREST"), data)), 0.1f, 1e-5f);
  // 32 tiles: λ = 1 between levels 0 and 2 for trilinear too.
  EXPECT_NEAR(grey(RenderCloth(ClothScene(32, false, 1, "LEVEL_MODE_TRILINEAR"), data)), 0.2f, 2e-3f);
  // Seen head-on the footprint is round: anisotropic shades once, where trilinear does.
  EXPECT_NEAR(grey(RenderCloth(ClothScene(32, false, 1, "LEVEL_MODE_ANISOTROPIC"), data)), 0.2f, 2e-3f);
  EXPECT_NEAR(grey(RenderCloth(ClothScene(64, false, 1, "LEVEL_MODE_ANISOTROPIC"), data)), 0.3f, 2e-3f);
}

TEST(SvbrdfFabric, LodBiasShiftsTheLevelWithinTheChainButNotLevelZeroOnly) {
  FabricTextureData data = DiffuseFabric(4, 3, glm::vec3(0.0f));  // levels 4, 2, 1 texels: greys 0.1, 0.2, 0.3
  for (uint32_t level = 0; level < data.levels(); ++level)
    for (uint32_t y = 0; y < data.LevelResolution(level); ++y)
      for (uint32_t x = 0; x < data.LevelResolution(level); ++x)
        data.Param(level, 0, x, y) = glm::vec4(glm::vec3(0.1f * (level + 1)), 0.0f);
  const auto grey = [&](const char* mode, float bias) {
    return RenderCloth(ClothScene(32, false, 1, mode, 0.0f, bias), data).image.at(30, 30, 0) / 2.0f;
  };
  // 32 tiles over 64 px: λ = 1.
  EXPECT_NEAR(grey("LEVEL_MODE_NEAREST", -1.0f), 0.1f, 1e-5f);
  EXPECT_NEAR(grey("LEVEL_MODE_NEAREST", 1.0f), 0.3f, 1e-5f);
  EXPECT_NEAR(grey("LEVEL_MODE_NEAREST", 3.0f), 0.3f, 1e-5f);  // clamped to the coarsest level
  EXPECT_NEAR(grey("LEVEL_MODE_TRILINEAR", -0.5f), 0.15f, 2e-3f);
  EXPECT_NEAR(grey("LEVEL_MODE_NONE", 1.0f), 0.1f, 1e-5f);  // level 0 whatever the bias
}

// Shaded per sample, each of 4 samples reads the level of its quarter of the
// footprint, one finer than the pixel's, where a tile spans more than 2^2.5 px
// (32 texels a tile: the pixel's footprint below level 2.5), and the pixel's own
// level below 2^1.5 px (level 3.5). Level 0 a black-and-white
// checkerboard of texels half a pixel wide where the footprint is level 1, every
// coarser level L a grey 0.1·L but level 4 a checkerboard of 0 and 0.8: shaded
// once per pixel, a pixel is a level's grey;
// once per sample near by, each sample (GL's standard 4× pattern puts one in each
// quarter of the pixel) reads its own level-0 texel and the pixel resolves to their
// mean, ½, the reference's box filter over the pixel.
TEST(SvbrdfFabric, SampleShadingReadsEverySamplesTexelAtItsShareOfTheFootprint) {
  // `resolution` texels a tile, level 0 a checkerboard of 0 and 1, level L a grey
  // 0.1·L, but level `checkered` a checkerboard of 0 and 0.8.
  const auto fabric = [](uint32_t resolution, uint32_t checkered) {
    FabricTextureData data = DiffuseFabric(resolution, 3, glm::vec3(0.0f));
    for (uint32_t level = 0; level < data.levels(); ++level)
      for (uint32_t y = 0; y < data.LevelResolution(level); ++y)
        for (uint32_t x = 0; x < data.LevelResolution(level); ++x) {
          const float checker = float((x + y) % 2);
          const float grey = level == 0 ? checker : level == checkered ? 0.8f * checker : 0.1f * level;
          data.Param(level, 0, x, y) = glm::vec4(glm::vec3(grey), 0.0f);
        }
    return data;
  };
  const FabricTextureData data = fabric(32, 4);  // levels 32, 16, 8, 4, 2, 1 texels
  // The greys inside the frame of `cloth`; the camera moved `shift` pixels along x.
  const auto greys = [](const FabricTextureData& cloth, float repeat, int msaa, const char* rate,
                        float shift = 0.0f) {
    std::string scene = ClothScene(repeat, false, msaa, "LEVEL_MODE_TRILINEAR", 0.0f, 0.0f, rate);
    const std::string at = R"("position": {"x": 0,)";
    const std::string x = std::to_string(shift * 2.0f / 64.0f);
    scene.replace(scene.find(at), at.size(), R"("target": {"x": )" + x + R"(}, "position": {"x": )" + x + ",");
    const Image image = RenderCloth(scene, cloth).image;
    std::vector<float> inside;
    for (int y = 8; y < 56; ++y)
      for (int x = 8; x < 56; ++x) inside.push_back(image.at(x, y, 0) / 2.0f);
    return inside;
  };
  // How many of `values` are none of `expected` (within 2e-3).
  const auto others = [](const std::vector<float>& values, std::vector<float> expected) {
    return std::count_if(values.begin(), values.end(), [&](float v) {
      return std::none_of(expected.begin(), expected.end(), [&](float e) { return std::abs(v - e) < 2e-3f; });
    });
  };
  // 4 tiles over 64 px at 32 texels a tile: 2 level-0 texels a pixel, λ = 1. Once
  // per sample each sample reads its own level-0 texel: the pixel their mean.
  EXPECT_EQ(others(greys(data, 4, 4, "SHADING_RATE_PIXEL"), {0.1f}), 0);
  EXPECT_EQ(others(greys(data, 4, 4, "SHADING_RATE_SAMPLE"), {0.5f}), 0);
  EXPECT_EQ(others(greys(data, 4, 1, "SHADING_RATE_SAMPLE"), {0.1f}), 0);  // one sample: a pixel's shading
  // 16 tiles: λ = 3, half the bias: λ 2.5, between the greys of levels 2 and 3.
  EXPECT_EQ(others(greys(data, 16, 4, "SHADING_RATE_SAMPLE"), {0.25f}), 0);
  // The span is a tile's, whatever its texels: 8 texels a tile, 16 tiles (a tile
  // 4 px across, λ = 1): half the bias, λ 0.5, the samples halfway to the centre
  // (still one in each quarter): ½ · ½ + ½ · 0.1.
  EXPECT_EQ(others(greys(fabric(8, 0), 16, 4, "SHADING_RATE_SAMPLE"), {0.3f}), 0);
  // 32 tiles: λ = 4, a level-4 texel a pixel: every sample reads the pixel's texel,
  // also with the texels' edges a quarter pixel off the pixels' (not ¼ and ¾ of one
  // texel and the next, as the samples' own places would).
  for (const float shift : {0.0f, 0.25f}) {
    for (const char* rate : {"SHADING_RATE_PIXEL", "SHADING_RATE_SAMPLE"}) {
      const std::vector<float> values = greys(data, 32, 4, rate, shift);
      EXPECT_EQ(others(values, {0.0f, 0.8f}), 0) << rate << " shifted " << shift;
      EXPECT_GT(std::count_if(values.begin(), values.end(), [](float v) { return v > 0.4f; }), 1000) << rate;
    }
  }
}

}  // namespace
}  // namespace loom
