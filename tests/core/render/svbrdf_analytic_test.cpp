// The whole svbrdf path against an analytic BRDF: radiance samples of a known
// Lafortune BRDF → FitFabric → GPU layout → render of a lit plane, compared pixel
// by pixel with the BRDF evaluated for that pixel's own view and light.

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "core/acquire/hemisphere_directions.h"
#include "core/fit/fabric_fit.h"
#include "core/render/fabric_textures.h"
#include "core/render/gpu_renderer.h"
#include "core/scene/camera.h"
#include "core/spec/defaults.h"
#include "core/spec/spec_json.h"
#include "core/spec/validate.h"

namespace loom {
namespace {

LafortuneBrdf KnownBrdf() {
  LafortuneBrdf brdf;
  brdf.lobe_count = 1;
  brdf.rho = {0.20f, 0.15f, 0.10f};
  brdf.lobes[0].cx = glm::vec3(-0.85f);
  brdf.lobes[0].cy = glm::vec3(-0.80f);
  brdf.lobes[0].cz = glm::vec3(0.90f);
  brdf.lobes[0].n = {12.0f, 10.0f, 8.0f};
  return brdf;
}

// Samples of KnownBrdf for every texel in the texel frame of `normal` (its tangent
// derived as acquisition derives it), no holes, T = 1.
RadianceSamples AnalyticSamples(uint32_t resolution, uint32_t directions, glm::vec3 normal) {
  RadianceSamples samples(resolution, HemisphereGridDirections(directions), HemisphereGridDirections(directions));
  const LafortuneBrdf brdf = KnownBrdf();
  const glm::vec3 tangent = TexelTangent(normal);
  const TexelFrame frame(normal, tangent);
  for (size_t texel = 0; texel < samples.texel_count(); ++texel) {
    samples.normals[texel] = normal;
    samples.tangents[texel] = tangent;
    for (size_t view = 0; view < samples.view_count(); ++view) {
      samples.alpha[samples.AlphaIndex(texel, view)] = 1.0f;
      for (size_t light = 0; light < samples.light_count(); ++light) {
        samples.radiance[samples.RadianceIndex(texel, view, light)] = brdf.Evaluate(
            frame.ToLocal(samples.light_directions[light]), frame.ToLocal(samples.view_directions[view]));
      }
    }
  }
  return samples;
}

// Fits the samples of KnownBrdf in the texel frame of `normal`, renders a lit plane
// with the fit (the plane's frame is the tile's: normal +z, tangent +x) and compares
// every pixel with KnownBrdf evaluated for that pixel's view and light in the same
// texel frame: the renderer's two mappings (world → surface → texel frame).
void ExpectRenderMatchesAnalyticBrdf(glm::vec3 normal) {
  v1::PrecomputeSettings settings;
  settings.set_lobes(1);
  const FittedFabric fit = FitFabric(AnalyticSamples(4, 64, normal), settings);
  const TexelFrame texel_frame(normal, TexelTangent(normal));

  const v1::SceneSpec scene = WithDefaults(ParseSpecJson<v1::SceneSpec>(R"({
    "objects": [{"mesh": {"builtin": "BUILTIN_SHAPE_PLANE"}, "transform": {"scale": {"x": 2, "y": 2, "z": 1}},
                 "fabric": {"fabric": {"knit": {}}, "repeat_u": 8, "repeat_v": 8}}],
    "camera": {"position": {"x": 0.3, "y": -1.6, "z": 1.5}, "target": {"x": 0, "y": 0, "z": 0}, "fov_y_degrees": 60},
    "lights": [{"direction": {"x": 0.3, "y": 0.7, "z": 1}, "intensity": 1.5}],
    "render": {"width": 96, "height": 64, "msaa_samples": 1}})", "scene"));
  ValidateOrThrow(scene);
  const auto context = gl::EglContext::Create();
  GpuRenderer renderer(*context);
  const auto meshes = BuildSceneGeometry(scene, FileMeshResolver("."));
  FabricTextures textures(FabricTextureData::FromFit(fit), /*half=*/false);
  // Every texel holds the same BRDF, so bilinear texels must shade as nearest ones do.
  for (const v1::TexelFilter filter : {v1::TEXEL_FILTER_NEAREST, v1::TEXEL_FILTER_BILINEAR}) {
    SCOPED_TRACE(v1::TexelFilter_Name(filter));
    v1::SceneSpec filtered = scene;
    filtered.mutable_render()->set_texel_filter(filter);
    const RenderedFrame frame = renderer.Render(filtered, meshes, {&textures});

    // Each pixel centre's ray, intersected with the plane z = 0.
    const int width = frame.image.width, height = frame.image.height;
    const CameraMatrices camera = MakeCameraMatrices(scene.camera(), static_cast<float>(width) / height);
    const glm::mat4 unproject = glm::inverse(camera.projection * camera.view);
    const glm::vec3 light = glm::normalize(glm::vec3(0.3f, 0.7f, 1.0f));
    const LafortuneBrdf brdf = KnownBrdf();
    int compared = 0;
    double worst = 0.0;
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        const glm::vec2 ndc((x + 0.5f) / width * 2.0f - 1.0f, 1.0f - (y + 0.5f) / height * 2.0f);
        const glm::vec4 near = unproject * glm::vec4(ndc, -1.0f, 1.0f);
        const glm::vec4 far = unproject * glm::vec4(ndc, 1.0f, 1.0f);
        const glm::vec3 origin = glm::vec3(near) / near.w, through = glm::vec3(far) / far.w;
        const float t = origin.z / (origin.z - through.z);
        const glm::vec3 hit = origin + t * (through - origin);
        // Skip pixels off the plane or on its rim (where the pixel mixes in the background).
        if (std::abs(hit.x) > 0.97f || std::abs(hit.y) > 0.97f) continue;
        const glm::vec3 expected = 1.5f * brdf.Evaluate(texel_frame.ToLocal(light),
                                                        texel_frame.ToLocal(glm::normalize(camera.position - hit)));
        for (int c = 0; c < 3; ++c) {
          const double error = std::abs(frame.image.at(x, y, c) - expected[c]);
          worst = std::max(worst, error / std::max(expected[c], 1e-3f));
          ASSERT_NEAR(frame.image.at(x, y, c), expected[c], 0.01f * expected[c] + 1e-5f)
              << "pixel " << x << "," << y << " channel " << c;
        }
        ++compared;
      }
    EXPECT_GT(compared, width * height / 4);  // the plane fills about a third of the frame
    std::printf("%s: compared %d pixels, worst relative error %.4f%%\n", v1::TexelFilter_Name(filter).c_str(),
                compared, 100.0 * worst);
  }
}

TEST(SvbrdfAnalytic, RenderOfAFittedAnalyticBrdfMatchesItPerPixelWithinOnePercent) {
  ExpectRenderMatchesAnalyticBrdf(glm::vec3(0, 0, 1));
}

// A texel frame tilted 25° from the tile's normal, so the lobe's mirror direction
// moves off the surface's and a renderer that shaded in the surface frame, or
// rotated the texel frame the wrong way, misses the highlight.
TEST(SvbrdfAnalytic, RenderMatchesTheAnalyticBrdfInATiltedTexelFrame) {
  ExpectRenderMatchesAnalyticBrdf(glm::normalize(glm::vec3(std::sin(glm::radians(25.0f)) * glm::vec2(0.6f, -0.8f),
                                                           std::cos(glm::radians(25.0f)))));
}

}  // namespace
}  // namespace loom
