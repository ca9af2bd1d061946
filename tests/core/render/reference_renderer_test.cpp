#include "core/render/reference_renderer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <glm/gtc/constants.hpp>
#include <algorithm>
#include <string>
#include <thread>
#include <vector>

#include "core/acquire/acquisition.h"
#include "core/acquire/hemisphere_directions.h"
#include "core/fabric/fabric_tile.h"
#include "core/spec/defaults.h"
#include "core/spec/spec_json.h"
#include "core/spec/validate.h"
#include "tests/core/render/comparison_scene.h"
#include "tests/core/render/image_probes.h"
#include "tests/core/render/point_shadow_scene.h"

namespace loom {
namespace {

using testing::MeanRed;
using testing::RedFraction;

ReferenceFrame RenderJson(const std::string& json, unsigned threads = 2) {
  const v1::SceneSpec scene = WithDefaults(ParseSpecJson<v1::SceneSpec>(json, "scene"));
  ValidateOrThrow(scene);
  return ReferenceRenderer(threads).Render(scene, BuildSceneGeometry(scene, FileMeshResolver(".")));
}

// An orthographic camera straight down on the 2 × 2 square about the origin.
constexpr const char* kTopCamera = R"("camera": {"projection": "PROJECTION_ORTHOGRAPHIC", "ortho_height": 2,
    "position": {"x": 0, "y": 0, "z": 5}, "up": {"x": 0, "y": 1, "z": 0}, "near": 0.1, "far": 10})";

// A white plain weave: diffuse albedo 0.8, no fibre lobe; or a yarn given in JSON.
constexpr const char* kWhiteYarn =
    R"({"diffuse_albedo": {"r": 0.8, "g": 0.8, "b": 0.8}, "specular_albedo": {"r": 0, "g": 0, "b": 0}})";
std::string WhiteWeave(float gap, const std::string& yarn = kWhiteYarn) {
  return R"({"woven": {"pattern": "WEAVE_PATTERN_PLAIN", "gap_ratio": )" + std::to_string(gap) + R"(}, "yarns": [)" +
         yarn + "]}";
}

// That weave on the 2 × 2 plane, 8 × 8 tiles, under a zenith light (or `light`, a
// Light's JSON); optionally over a red plane.
constexpr const char* kZenithLight = R"({"direction": {"x": 0, "y": 0, "z": 1}, "intensity": 1})";
std::string ClothScene(float gap, bool red_floor, int size, int samples, const std::string& yarn = kWhiteYarn,
                       const std::string& light = kZenithLight) {
  const std::string floor = red_floor ? R"(, {"mesh": {"builtin": "BUILTIN_SHAPE_PLANE"},
      "transform": {"translation": {"z": -0.5}, "scale": {"x": 4, "y": 4, "z": 1}}, "base_colour": {"r": 1, "g": 0, "b": 0}})"
                                      : "";
  const std::string side = std::to_string(size);
  return R"({"objects": [{"mesh": {"builtin": "BUILTIN_SHAPE_PLANE"}, "transform": {"scale": {"x": 2, "y": 2, "z": 1}},
      "fabric": {"fabric": )" + WhiteWeave(gap, yarn) + R"(, "repeat_u": 8, "repeat_v": 8}})" + floor + "], " + kTopCamera + R"(,
    "lights": [)" + light + R"(],
    "render": {"method": "RENDER_METHOD_REFERENCE", "width": )" + side + R"(, "height": )" + side +
         R"(, "reference_samples": )" + std::to_string(samples) + "}}";
}

TEST(ReferenceRenderer, LambertianPlaneUnderAZenithLightIsAlbedoOverPiTimesIrradiance) {
  const ReferenceFrame frame = RenderJson(std::string(R"({"objects": [{"mesh": {"builtin": "BUILTIN_SHAPE_PLANE"},
      "transform": {"scale": {"x": 2, "y": 2, "z": 1}}, "base_colour": {"r": 0.6, "g": 0.3, "b": 0.15}}], )") +
      kTopCamera + R"(, "lights": [{"direction": {"x": 0, "y": 0, "z": 1}, "intensity": 2.5, "casts_shadows": true}],
      "render": {"width": 48, "height": 48, "reference_samples": 4}})");
  const glm::vec3 albedo(0.6f, 0.3f, 0.15f);
  for (int y = 0; y < 48; ++y) {
    for (int x = 0; x < 48; ++x) {
      for (int c = 0; c < 3; ++c) {
        ASSERT_NEAR(frame.image.at(x, y, c), albedo[c] / glm::pi<float>() * 2.5f, 1e-4f) << x << "," << y;
      }
    }
  }
}

// Ties the reference to acquisition: the same fabric seen head-on under a zenith
// light has the mean radiance of acquisition's samples for the zenith view and light,
// whichever model its yarn shades with.
// What acquisition says the reference's frame holds: the weave's samples (16 texels,
// 3 × 3 views and lights, 4 × 4 supersampling) for the zenith view under light
// `light` of `side`'s grid, which must point to `towards_light`, red channel times
// coverage, averaged over the texels.
double AcquiredAtTheZenith(float gap, const std::string& yarn, size_t light, glm::vec3 towards_light,
                           LightSide side) {
  v1::PrecomputeSettings settings;
  settings.set_spatial_resolution(16);
  settings.set_view_directions(9);  // a 3 × 3 grid: the centre direction is the zenith
  settings.set_light_directions(9);
  settings.set_supersampling(4);
  const RadianceSamples samples =
      Acquire(BuildFabricTile(WithDefaults(ParseSpecJson<v1::FabricSpec>(WhiteWeave(gap, yarn), "fabric"))),
              settings, {}, nullptr, {}, side);
  constexpr size_t kZenith = 4;
  EXPECT_NEAR(samples.view_directions[kZenith].z, 1.0f, 1e-6f);
  EXPECT_NEAR(glm::distance(samples.light_directions[light], towards_light), 0.0f, 1e-5f);
  double acquired = 0.0;
  for (size_t texel = 0; texel < samples.texel_count(); ++texel) {
    acquired += samples.radiance[samples.RadianceIndex(texel, kZenith, light)].r *
                samples.alpha[samples.AlphaIndex(texel, kZenith)];
  }
  return acquired / static_cast<double>(samples.texel_count());
}

class ReferenceRendererYarn : public ::testing::TestWithParam<const char*> {};
INSTANTIATE_TEST_SUITE_P(
    Models, ReferenceRendererYarn,
    ::testing::Values(kWhiteYarn, R"({"shading": "YARN_SHADING_MICROFLAKE", "roughness": 0.3, "height_scale": 0.5,
        "diffuse_albedo": {"r": 0.5, "g": 0.5, "b": 0.5}, "specular_albedo": {"r": 0.5, "g": 0.5, "b": 0.5}})"),
    [](const ::testing::TestParamInfo<const char*>& info) { return info.index == 0 ? "KajiyaKay" : "Microflake"; });

TEST_P(ReferenceRendererYarn, ClothPlaneMatchesAcquisitionAtTheZenith) {
  const double rendered = MeanRed(RenderJson(ClothScene(0.0f, false, 48, 16, GetParam())).image);
  constexpr size_t kZenith = 4;  // of the 3 × 3 light grid
  const double acquired = AcquiredAtTheZenith(0.0f, GetParam(), kZenith, {0, 0, 1}, LightSide::kFront);
  EXPECT_GT(acquired, 0.1);
  EXPECT_NEAR(rendered, acquired, 0.02 * acquired);
}

TEST(ReferenceRenderer, AThinWeaveLitFromBehindGlowsAsAcquisitionSaysItDoes) {
  // Light from below the cloth, casting shadows (so it must leave the shell through
  // its bottom): a microflake weave passes it through its yarns; the camera above sees
  // acquisition's back-lit samples (LightSide::kBack) for the zenith view.
  const std::string yarn = R"({"shading": "YARN_SHADING_MICROFLAKE", "roughness": 0.3, "diffuse_transmission": 0.5,
      "diffuse_albedo": {"r": 0.5, "g": 0.5, "b": 0.5}, "specular_albedo": {"r": 0.4, "g": 0.4, "b": 0.4}})";
  constexpr size_t kLight = 5;  // of a 3 × 3 grid, towards +x; mirrored below
  const glm::vec3 below = HemisphereGridDirections(9)[kLight] * glm::vec3(1, 1, -1);
  const std::string light = R"({"direction": {"x": )" + std::to_string(below.x) + R"(, "y": )" + std::to_string(below.y) +
                            R"(, "z": )" + std::to_string(below.z) + R"(}, "intensity": 1, "casts_shadows": true})";
  const double rendered = MeanRed(RenderJson(ClothScene(0.1f, false, 48, 16, yarn, light)).image);
  const double acquired = AcquiredAtTheZenith(0.1f, yarn, kLight, below, LightSide::kBack);
  std::printf("back-lit thin weave: reference %.5f, acquisition %.5f\n", rendered, acquired);
  EXPECT_GT(acquired, 0.005);  // a light below the surface, blocked, leaves 0
  EXPECT_NEAR(rendered, acquired, 0.02 * acquired);
}

TEST(ReferenceRenderer, HolesOfALooseWeaveShowTheRedPlaneBelow) {
  const double loose = RedFraction(RenderJson(ClothScene(0.4f, true, 48, 4)).image);
  const double dense = RedFraction(RenderJson(ClothScene(0.0f, true, 48, 4)).image);
  EXPECT_GT(loose, 0.02);
  EXPECT_LT(dense, 0.02);
}

// The weave's shadow on the red plane 0.5 below it, cast by a light 45° off the
// zenith towards +x, covers x ∈ [−1.5, 0.5]; x < −1 of it is not under the cloth.
// The camera sees x, y ∈ [−2, 2].
double MeanRedBesideTheCloth(float gap) {
  const std::string scene = R"({"objects": [{"mesh": {"builtin": "BUILTIN_SHAPE_PLANE"},
      "transform": {"scale": {"x": 2, "y": 2, "z": 1}},
      "fabric": {"fabric": )" + WhiteWeave(gap) + R"(, "repeat_u": 8, "repeat_v": 8}},
      {"mesh": {"builtin": "BUILTIN_SHAPE_PLANE"}, "transform": {"translation": {"z": -0.5}, "scale": {"x": 4, "y": 4, "z": 1}},
       "base_colour": {"r": 1, "g": 0, "b": 0}}],
    "camera": {"projection": "PROJECTION_ORTHOGRAPHIC", "ortho_height": 4, "position": {"x": 0, "y": 0, "z": 5},
               "up": {"x": 0, "y": 1, "z": 0}, "near": 0.1, "far": 10},
    "lights": [{"direction": {"x": 1, "y": 0, "z": 1}, "intensity": 1, "casts_shadows": true}],
    "render": {"width": 48, "height": 48, "reference_samples": 4}})";
  const Image image = RenderJson(scene).image;
  // Pixels over x ∈ [−1.4, −1.1], y ∈ [−0.8, 0.8]: in the shadow, not under the cloth.
  double sum = 0.0;
  int count = 0;
  for (int y = 14; y < 34; ++y)
    for (int x = 8; x < 11; ++x, ++count) sum += image.at(x, y, 0);
  return sum / count;
}

TEST(ReferenceRenderer, ALooseWeaveCastsALacyShadow) {
  const float lit = 1.0f / glm::pi<float>() * std::sqrt(0.5f);  // the red plane, unshadowed
  const double loose = MeanRedBesideTheCloth(0.4f);
  const double dense = MeanRedBesideTheCloth(0.0f);
  EXPECT_LT(dense, 0.02 * lit);
  EXPECT_GT(loose, 0.05 * lit);
  EXPECT_LT(loose, 0.9 * lit);
}

// The locally flat shell on curved surfaces at the largest supported repeat.
TEST(ReferenceRenderer, KnitSphereAndCylinderAt64x64Render) {
  for (const char* shape : {"BUILTIN_SHAPE_SPHERE", "BUILTIN_SHAPE_CYLINDER"}) {
    const Image image = RenderJson(std::string(R"({"objects": [{"mesh": {"builtin": ")") + shape + R"("},
        "fabric": {"fabric": {"knit": {}}, "repeat_u": 64, "repeat_v": 64}}],
      "camera": {"position": {"x": 0, "y": -4, "z": 0.5}, "target": {"x": 0, "y": 0, "z": 0}},
      "lights": [{"direction": {"x": 0.3, "y": -1, "z": 0.5}, "intensity": 3, "casts_shadows": true}],
      "background": {"r": 0, "g": 0, "b": 1},
      "render": {"width": 32, "height": 32, "reference_samples": 4}})").image;
    int lit = 0;
    for (float value : image.pixels) ASSERT_TRUE(std::isfinite(value)) << shape;
    for (int y = 0; y < 32; ++y)
      for (int x = 0; x < 32; ++x) lit += image.at(x, y, 0) > 0.05f;
    EXPECT_GT(lit, 32) << shape;  // yarn covers part of the frame
  }
}

// A point light's shadow ray ends at the light: the sphere's shadow falls where the
// rays to it meet the sphere (as the GPU renderer's cube maps, svbrdf_renderer_test.cpp).
TEST(ReferenceRenderer, APointLightsShadowFallsWhereItsRaysMeetTheSphere) {
  // Lambert's at the pixel's centre; the reference averages samples over the pixel.
  testing::ExpectShadowWhereTheRaysMeetTheSphere([](const std::string& json) { return RenderJson(json).image; },
                                                 "RENDER_METHOD_REFERENCE", 2e-2);
}

TEST(ReferenceRenderer, FramesAreBitIdenticalWhateverTheThreadCount) {
  const std::string scene = ClothScene(0.4f, true, 24, 4);
  const ReferenceFrame one = RenderJson(scene, 1);
  const ReferenceFrame two = RenderJson(scene, 2);
  EXPECT_EQ(one.image.pixels, two.image.pixels);
  EXPECT_EQ(one.rays, two.rays);
}

// A long reference render reports progress (so a worker's lease and liveness see
// it move) on the calling thread, rising to 1; throwing from it abandons the render.
TEST(ReferenceRenderer, ProgressRisesToOneOnTheCallingThreadAndThrowingAbandons) {
  const v1::SceneSpec scene = WithDefaults(ParseSpecJson<v1::SceneSpec>(ClothScene(0.0f, false, 24, 1), "scene"));
  const auto meshes = BuildSceneGeometry(scene, FileMeshResolver("."));
  // With two threads the other may render every row while the caller is on its
  // first, which then reports only the end: how many reports come is the scheduler's.
  const std::thread::id caller = std::this_thread::get_id();
  std::vector<double> fractions;
  ReferenceRenderer(2).Render(scene, meshes, [&](double fraction, std::string_view stage) {
    EXPECT_EQ(std::this_thread::get_id(), caller);
    EXPECT_EQ(stage, "rendering");
    fractions.push_back(fraction);
  });
  ASSERT_GE(fractions.size(), 1u);
  EXPECT_TRUE(std::is_sorted(fractions.begin(), fractions.end()));
  EXPECT_EQ(fractions.back(), 1.0);

  // On the calling thread alone, a report per row (24 rows, every 1%).
  fractions.clear();
  ReferenceRenderer(1).Render(scene, meshes, [&](double fraction, std::string_view) { fractions.push_back(fraction); });
  EXPECT_EQ(fractions.size(), 24u + 1u);  // each row, and the end
  EXPECT_TRUE(std::is_sorted(fractions.begin(), fractions.end()));

  struct Abandoned {};
  int calls = 0;
  EXPECT_THROW(ReferenceRenderer(1).Render(scene, meshes,
                                           [&](double, std::string_view) {
                                             if (++calls == 2) throw Abandoned{};
                                           }),
               Abandoned);
  EXPECT_EQ(calls, 2);
}

}  // namespace
}  // namespace loom
