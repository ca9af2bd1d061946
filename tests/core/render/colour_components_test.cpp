// A colour edit without a precompute (PrecomputeSettings.colour_components,
// core/methods/colour_sheets.h): a fabric that differs from a precomputed one only
// in its yarns' albedos renders from that fabric's asset, its colours applied per
// sheet by the renderer, as a full precompute of it renders.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "core/gl/egl_context.h"
#include "core/precompute/fabric_precompute.h"
#include "core/render/gpu_renderer.h"
#include "core/render/scene_render.h"
#include "core/spec/defaults.h"
#include "core/spec/fabric_key.h"
#include "core/spec/spec_json.h"
#include "core/spec/validate.h"

namespace loom {
namespace {

// A two-colour microflake twill lit from above and from behind, with ambient light,
// all coloured: every term the renderer adds (lights, back sheet, ambient) goes
// through the yarns' colours before the light's colour multiplies it.
v1::SceneSpec TwillScene(const char* warp, const char* weft, bool colour_components, v1::ShadingPass pass) {
  v1::SceneSpec scene = ParseSpecJson<v1::SceneSpec>(std::string(R"({"objects": [
      {"mesh": {"builtin": "BUILTIN_SHAPE_PLANE"}, "transform": {"scale": {"x": 2, "y": 2, "z": 1}},
       "fabric": {"fabric": {"woven": {"pattern": "WEAVE_PATTERN_TWILL", "gap_ratio": 0.2,
                                       "warp_colours": [0], "weft_colours": [1]},
                             "yarns": [{"shading": "YARN_SHADING_MICROFLAKE", "roughness": 0.3,
                                        "diffuse_transmission": 0.4, )") + warp + R"(},
                                       {"roughness": 0.4, )" + weft + R"(}]},
                  "precompute": {"method": "FABRIC_METHOD_TABULATED", "spatial_resolution": 16,
                                 "view_directions": 36, "light_directions": 36, "indirect_bounces": 0,
                                 "half_float": false},
                  "repeat_u": 6, "repeat_v": 6}}],
    "camera": {"projection": "PROJECTION_ORTHOGRAPHIC", "ortho_height": 1.6, "position": {"x": 0, "y": -2, "z": 4},
               "target": {"x": 0, "y": 0, "z": 0}, "up": {"x": 0, "y": 1, "z": 0}, "near": 0.1, "far": 10},
    "ambient": {"r": 0.04, "g": 0.05, "b": 0.08},
    "lights": [{"direction": {"x": -0.3, "y": -0.4, "z": 1}, "intensity": 1.5, "colour": {"r": 1, "g": 0.8, "b": 0.5}},
               {"direction": {"x": 0.3, "y": 0.2, "z": -1}, "intensity": 1, "colour": {"r": 0.6, "g": 0.8, "b": 1}}],
    "render": {"width": 48, "height": 48, "msaa_samples": 4}})",
                                                     "scene");
  v1::FabricBinding& binding = *scene.mutable_objects(0)->mutable_fabric();
  binding.mutable_precompute()->set_colour_components(colour_components);
  scene.mutable_render()->set_shading_pass(pass);
  scene = WithDefaults(scene);
  ValidateOrThrow(scene);
  return scene;
}

constexpr const char* kRedWarp =
    R"("diffuse_albedo": {"r": 0.7, "g": 0.2, "b": 0.1}, "specular_albedo": {"r": 0.2, "g": 0.2, "b": 0.2})";
constexpr const char* kBlueWeft =
    R"("diffuse_albedo": {"r": 0.1, "g": 0.3, "b": 0.6}, "specular_albedo": {"r": 0.1, "g": 0.1, "b": 0.1})";
constexpr const char* kGreenWarp =
    R"("diffuse_albedo": {"r": 0.1, "g": 0.6, "b": 0.2}, "specular_albedo": {"r": 0.05, "g": 0.3, "b": 0.1})";
constexpr const char* kYellowWeft =
    R"("diffuse_albedo": {"r": 0.8, "g": 0.7, "b": 0.1}, "specular_albedo": {"r": 0.15, "g": 0.15, "b": 0.0})";

GpuRenderer& Renderer() {
  static const auto context = gl::EglContext::Create();
  static GpuRenderer renderer(*context);
  return renderer;
}

std::string KeyOf(const v1::SceneSpec& scene) {
  const v1::FabricBinding& binding = scene.objects(0).fabric();
  return FabricKey(binding.fabric(), binding.precompute());
}

std::unique_ptr<FabricAsset> Precompute(const v1::SceneSpec& scene) {
  const v1::FabricBinding& binding = scene.objects(0).fabric();
  return PrecomputeAsset(binding.fabric(), binding.precompute());
}

Image Render(const v1::SceneSpec& scene, const FabricAsset& asset) {
  return RenderScene(Renderer(), scene, BuildSceneGeometry(scene, FileMeshResolver(".")), {{KeyOf(scene), &asset}})
      .image;
}

double LargestDifference(const Image& a, const Image& b) {
  double largest = 0.0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x)
      for (int c = 0; c < 3; ++c) largest = std::max(largest, double{std::abs(a.at(x, y, c) - b.at(x, y, c))});
  return largest;
}

double Brightest(const Image& image) {
  double brightest = 0.0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      for (int c = 0; c < 3; ++c) brightest = std::max(brightest, double{image.at(x, y, c)});
  return brightest;
}

class ColourComponentsTest : public ::testing::TestWithParam<v1::ShadingPass> {};

// The tabulated method stores its samples, so the edit and the full precompute differ
// only by float rounding: the bound is the issue's, 1e-3 of radiance. Rendering the
// edit with the original's colours (what a renderer ignoring the edit would draw) is
// far off, and so is the RGB asset of the original.
TEST_P(ColourComponentsTest, AColourEditRendersAsAFullPrecomputeOfTheEditedFabric) {
  const v1::SceneSpec original = TwillScene(kRedWarp, kBlueWeft, true, GetParam());
  const v1::SceneSpec edited = TwillScene(kGreenWarp, kYellowWeft, true, GetParam());
  ASSERT_EQ(KeyOf(edited), KeyOf(original));
  const std::unique_ptr<FabricAsset> asset = Precompute(original);
  ASSERT_EQ(asset->colour_sheets().size(), 1u);
  ASSERT_NE(asset->back(), nullptr);
  ASSERT_NE(asset->colour_sheets()[0]->back(), nullptr);
  const Image edit = Render(edited, *asset);

  const v1::SceneSpec edited_rgb = TwillScene(kGreenWarp, kYellowWeft, false, GetParam());
  const Image full = Render(edited_rgb, *Precompute(edited_rgb));
  const Image unedited = Render(original, *asset);
  std::printf("brightest %.4f; the edit against a full precompute: %.2e; against the original's colours: %.3f\n",
              Brightest(full), LargestDifference(edit, full), LargestDifference(unedited, full));
  EXPECT_GT(Brightest(full), 0.05);
  EXPECT_LT(LargestDifference(edit, full), 1e-3);
  EXPECT_GT(LargestDifference(unedited, full), 0.05);

  // The asset's files carry the sheets and their channels.
  const std::filesystem::path directory =
      std::filesystem::path(::testing::TempDir()) / ("colour-components-" + std::to_string(GetParam()));
  std::filesystem::remove_all(directory);
  asset->Write(original.objects(0).fabric().precompute(), KeyOf(original), directory);
  EXPECT_LT(LargestDifference(Render(edited, *ReadAnyFabricAsset(directory)), edit), 1e-6);
  std::filesystem::remove(directory / kColourSheetsFile);
  EXPECT_THROW(ReadAnyFabricAsset(directory), Error);
  std::filesystem::remove_all(directory);
}

INSTANTIATE_TEST_SUITE_P(BothShadingPasses, ColourComponentsTest,
                         ::testing::Values(v1::SHADING_PASS_FRAGMENT, v1::SHADING_PASS_COMPUTE),
                         [](const auto& info) { return std::string(v1::ShadingPass_Name(info.param)).substr(13); });

}  // namespace
}  // namespace loom
