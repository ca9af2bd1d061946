// The compute shading pass (render.shading_pass COMPUTE; GpuRenderer, ClothGbuffer,
// core/shaders/cloth.glsl): the same frame as the fragment pass for every method,
// shading in place only the fragments its G-buffers cannot hold.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include "core/gl/egl_context.h"
#include "core/metrics/image_metrics.h"
#include "core/precompute/fabric_precompute.h"
#include "core/render/gpu_renderer.h"
#include "core/render/scene_render.h"
#include "core/spec/defaults.h"
#include "core/spec/fabric_key.h"
#include "core/spec/spec_json.h"
#include "core/spec/validate.h"

namespace loom {
namespace {

constexpr int kWidth = 128, kHeight = 96;

// A loose weave draped over a ball (two layers of cloth behind one pixel where the
// near one has holes, silhouettes against the red floor), seen in perspective under
// a shadow-casting light, 4× MSAA.
v1::SceneSpec DrapeScene(v1::FabricMethod method, v1::ShadingPass pass,
                         v1::ShadingRate rate = v1::SHADING_RATE_PIXEL) {
  v1::SceneSpec scene = ParseSpecJson<v1::SceneSpec>(R"({"objects": [
      {"mesh": {"builtin": "BUILTIN_SHAPE_DRAPE"},
       "fabric": {"fabric": {"woven": {"pattern": "WEAVE_PATTERN_PLAIN", "gap_ratio": 0.4}},
                  "precompute": {"spatial_resolution": 16, "view_directions": 36, "light_directions": 36,
                                 "lobes": 1, "neural": {"steps": 50}},
                  "repeat_u": 10, "repeat_v": 10}},
      {"mesh": {"builtin": "BUILTIN_SHAPE_PLANE"}, "transform": {"translation": {"z": -0.7}, "scale": {"x": 6, "y": 6, "z": 1}},
       "base_colour": {"r": 1, "g": 0, "b": 0}}],
    "camera": {"projection": "PROJECTION_PERSPECTIVE", "fov_y_degrees": 40, "position": {"x": 0.6, "y": -2.6, "z": 1.4},
               "target": {"x": 0, "y": 0, "z": -0.1}, "up": {"x": 0, "y": 0, "z": 1}},
    "lights": [{"direction": {"x": -0.4, "y": -0.5, "z": 1}, "intensity": 3, "casts_shadows": true}],
    "ambient": {"r": 0.05, "g": 0.05, "b": 0.05},
    "render": {"width": 128, "height": 96, "msaa_samples": 4}})",
                                                     "scene");
  scene.mutable_objects(0)->mutable_fabric()->mutable_precompute()->set_method(method);
  scene.mutable_render()->set_shading_pass(pass);
  scene.mutable_render()->set_shading_rate(rate);
  scene = WithDefaults(scene);
  ValidateOrThrow(scene);
  return scene;
}

class ComputePassTest : public ::testing::TestWithParam<v1::FabricMethod> {
 protected:
  RenderedFrame Render(const v1::SceneSpec& scene) {
    static const auto context = gl::EglContext::Create();
    static GpuRenderer renderer(*context);
    const auto meshes = BuildSceneGeometry(scene, FileMeshResolver("."));
    const v1::FabricBinding& binding = scene.objects(0).fabric();
    if (!asset_) asset_ = PrecomputeAsset(binding.fabric(), binding.precompute());
    return RenderScene(renderer, scene, meshes, {{FabricKey(binding.fabric(), binding.precompute()), asset_.get()}});
  }
  std::unique_ptr<FabricAsset> asset_;
};

// The compute pass shades the nearest two layers of cloth per pixel from its
// G-buffers and blends them as the fragment pass does: the frames agree to float
// rounding (the G-buffer's derivatives and depths are the fragment pass's); only
// silhouette pixels and a third layer are shaded in place.
TEST_P(ComputePassTest, GivesTheFragmentPassesFrameShadingFewFragmentsInPlace) {
  const RenderedFrame fragment = Render(DrapeScene(GetParam(), v1::SHADING_PASS_FRAGMENT));
  const RenderedFrame compute = Render(DrapeScene(GetParam(), v1::SHADING_PASS_COMPUTE));
  EXPECT_FALSE(fragment.compute_pass);
  EXPECT_TRUE(compute.compute_pass);
  const ImageComparison comparison = CompareImages(compute.image, fragment.image);
  std::printf("compute against fragment pass: PSNR %.1f dB, %llu fragments shaded in place of %d pixels\n",
              comparison.psnr_db, static_cast<unsigned long long>(compute.shaded_in_place), kWidth * kHeight);
  EXPECT_GT(comparison.psnr_db, 50.0);
  EXPECT_GT(compute.shaded_in_place, 0u);  // the drape's silhouettes
  EXPECT_LT(compute.shaded_in_place, static_cast<uint64_t>(0.05 * kWidth * kHeight));
}

// The G-buffers hold a sample a pixel: shaded per sample, the frame takes the
// fragment pass whatever the setting says.
TEST_P(ComputePassTest, ShadingPerSampleTakesTheFragmentPass) {
  const RenderedFrame frame = Render(DrapeScene(GetParam(), v1::SHADING_PASS_COMPUTE, v1::SHADING_RATE_SAMPLE));
  EXPECT_FALSE(frame.compute_pass);
  EXPECT_EQ(frame.shaded_in_place, 0u);
}

INSTANTIATE_TEST_SUITE_P(EveryMethod, ComputePassTest,
                         ::testing::Values(v1::FABRIC_METHOD_SVBRDF, v1::FABRIC_METHOD_TABULATED,
                                           v1::FABRIC_METHOD_FACTORED, v1::FABRIC_METHOD_NEURAL),
                         [](const auto& info) { return std::string(v1::FabricMethod_Name(info.param)).substr(14); });

}  // namespace
}  // namespace loom
