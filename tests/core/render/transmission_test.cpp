// Light through cloth on the GPU (FabricAsset::back, GpuRenderer's back sheet) against
// the reference renderer tracing the same light through the yarns.

#include <gtest/gtest.h>

#include <cstdio>
#include <memory>
#include <string>

#include "core/gl/egl_context.h"
#include "core/precompute/fabric_precompute.h"
#include "core/render/gpu_renderer.h"
#include "core/render/reference_renderer.h"
#include "core/render/scene_render.h"
#include "core/spec/defaults.h"
#include "core/spec/fabric_key.h"
#include "core/spec/spec_json.h"
#include "core/spec/validate.h"

namespace loom {
namespace {

constexpr int kSize = 48;

// A microflake plain weave filling the frame, seen from above, lit only from below
// (no ambient): what the camera sees is light that came through the yarns.
v1::SceneSpec BackLitWeave(v1::FabricMethod method, bool transmission) {
  v1::SceneSpec scene = ParseSpecJson<v1::SceneSpec>(R"({"objects": [
      {"mesh": {"builtin": "BUILTIN_SHAPE_PLANE"}, "transform": {"scale": {"x": 2, "y": 2, "z": 1}},
       "fabric": {"fabric": {"woven": {"pattern": "WEAVE_PATTERN_PLAIN", "gap_ratio": 0.1},
                             "yarns": [{"shading": "YARN_SHADING_MICROFLAKE", "roughness": 0.3, "diffuse_transmission": 0.5,
                                        "diffuse_albedo": {"r": 0.5, "g": 0.5, "b": 0.5},
                                        "specular_albedo": {"r": 0.4, "g": 0.4, "b": 0.4}}]},
                  "precompute": {"spatial_resolution": 16, "view_directions": 36, "light_directions": 36, "lobes": 1},
                  "repeat_u": 8, "repeat_v": 8}}],
    "camera": {"projection": "PROJECTION_ORTHOGRAPHIC", "ortho_height": 1.6, "position": {"x": 0, "y": -0.5, "z": 5},
               "target": {"x": 0, "y": 0, "z": 0}, "up": {"x": 0, "y": 1, "z": 0}, "near": 0.1, "far": 10},
    "lights": [{"direction": {"x": 0.3, "y": 0.2, "z": -1}, "intensity": 2}],
    "render": {"width": 48, "height": 48, "msaa_samples": 4, "reference_samples": 16}})",
                                                     "scene");
  v1::PrecomputeSettings& settings = *scene.mutable_objects(0)->mutable_fabric()->mutable_precompute();
  settings.set_method(method);
  settings.set_transmission(transmission);
  scene = WithDefaults(scene);
  ValidateOrThrow(scene);
  return scene;
}

double MeanRadiance(const Image& image) {
  double sum = 0.0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) sum += image.at(x, y, 0) + image.at(x, y, 1) + image.at(x, y, 2);
  return sum / (3.0 * image.width * image.height);
}

double RenderGpu(const v1::SceneSpec& scene) {
  static const auto context = gl::EglContext::Create();
  static GpuRenderer renderer(*context);
  const v1::FabricBinding& binding = scene.objects(0).fabric();
  const std::unique_ptr<FabricAsset> asset = PrecomputeAsset(binding.fabric(), binding.precompute());
  return MeanRadiance(RenderScene(renderer, scene, BuildSceneGeometry(scene, FileMeshResolver(".")),
                                  {{FabricKey(binding.fabric(), binding.precompute()), asset.get()}})
                          .image);
}

// A method and how close its back sheet comes to the reference on this weave.
struct MethodBound {
  v1::FabricMethod method;
  double tolerance;  // relative
};

class TransmissionTest : public ::testing::TestWithParam<MethodBound> {};

// The back sheet carries what the front cannot: lit from behind, the cloth glows as
// the reference says it does; without the back sheet it is black. The table methods
// store the back-lit samples and come within a few per cent; svbrdf's Lafortune lobes
// fit them less well (docs/yarn_shading.md, "Light through the yarn").
TEST_P(TransmissionTest, ABackLitWeaveGlowsAsTheReferenceSays) {
  const v1::SceneSpec scene = BackLitWeave(GetParam().method, true);
  const double reference =
      MeanRadiance(ReferenceRenderer(2).Render(scene, BuildSceneGeometry(scene, FileMeshResolver("."))).image);
  const double gpu = RenderGpu(scene);
  const double without = RenderGpu(BackLitWeave(GetParam().method, false));
  std::printf("back-lit weave, mean radiance: reference %.5f, GPU %.5f, GPU without the back sheet %.5f\n", reference,
              gpu, without);
  EXPECT_GT(reference, 0.005);
  EXPECT_NEAR(gpu, reference, GetParam().tolerance * reference);
  EXPECT_LT(without, 0.01 * reference);
}

INSTANTIATE_TEST_SUITE_P(TableAndFittedMethods, TransmissionTest,
                         ::testing::Values(MethodBound{v1::FABRIC_METHOD_SVBRDF, 0.3},
                                           MethodBound{v1::FABRIC_METHOD_TABULATED, 0.05},
                                           MethodBound{v1::FABRIC_METHOD_FACTORED, 0.05}),
                         [](const auto& info) {
                           return std::string(v1::FabricMethod_Name(info.param.method)).substr(14);
                         });

}  // namespace
}  // namespace loom
