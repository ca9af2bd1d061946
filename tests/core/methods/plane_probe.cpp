#include "tests/core/methods/plane_probe.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>

#include "core/methods/direction_grid.h"
#include "core/render/gpu_renderer.h"
#include "core/scene/camera.h"
#include "core/spec/defaults.h"
#include "core/spec/spec_json.h"
#include "core/spec/validate.h"

namespace loom {

PlaneProbe ProbePlane(const FabricAsset& asset, uint32_t resolution, const std::vector<float>& view_heights,
                      const TexelEvaluation& evaluate) {
  const float repeat = 3.0f;
  const v1::SceneSpec scene = WithDefaults(ParseSpecJson<v1::SceneSpec>(R"({
    "objects": [{"mesh": {"builtin": "BUILTIN_SHAPE_PLANE"}, "transform": {"scale": {"x": 2, "y": 2, "z": 1}},
                 "fabric": {"fabric": {"knit": {}}, "repeat_u": 3, "repeat_v": 3}}],
    "camera": {"position": {"x": 0.3, "y": -1.6, "z": 1.5}, "target": {"x": 0, "y": 0, "z": 0}, "fov_y_degrees": 60},
    "lights": [{"direction": {"x": 0.3, "y": 0.7, "z": 1}, "intensity": 1.5}],
    "render": {"width": 96, "height": 64, "msaa_samples": 1, "level_mode": "LEVEL_MODE_NONE",
               "texel_filter": "TEXEL_FILTER_NEAREST"}})", "scene"));
  ValidateOrThrow(scene);
  static const auto context = gl::EglContext::Create();
  GpuRenderer renderer(*context);
  const auto meshes = BuildSceneGeometry(scene, FileMeshResolver("."));
  const std::unique_ptr<GpuFabric> gpu = asset.Upload(/*half=*/false);
  const RenderedFrame frame = renderer.Render(scene, meshes, {gpu.get()});

  const int width = frame.image.width, height = frame.image.height;
  const CameraMatrices camera = MakeCameraMatrices(scene.camera(), static_cast<float>(width) / height);
  const glm::mat4 unproject = glm::inverse(camera.projection * camera.view);
  const glm::vec3 light = glm::normalize(glm::vec3(0.3f, 0.7f, 1.0f));
  PlaneProbe probe;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const glm::vec2 ndc((x + 0.5f) / width * 2.0f - 1.0f, 1.0f - (y + 0.5f) / height * 2.0f);
      const glm::vec4 near = unproject * glm::vec4(ndc, -1.0f, 1.0f);
      const glm::vec4 far = unproject * glm::vec4(ndc, 1.0f, 1.0f);
      const glm::vec3 origin = glm::vec3(near) / near.w, through = glm::vec3(far) / far.w;
      const glm::vec3 hit = origin + origin.z / (origin.z - through.z) * (through - origin);
      if (std::abs(hit.x) > 0.97f || std::abs(hit.y) > 0.97f) continue;
      const glm::vec3 view = glm::normalize(camera.position - hit);
      const glm::vec2 uv(0.5f * hit.x + 0.5f, 0.5f * hit.y + 0.5f);
      const glm::vec2 tile = FabricTileAt(uv * repeat, view, view_heights);
      const glm::vec2 at = glm::fract(tile) * static_cast<float>(resolution);
      const glm::vec2 inside = at - glm::floor(at);
      // Skip pixels on a texel's edge, where rounding may pick either texel.
      if (glm::any(glm::lessThan(inside, glm::vec2(0.02f))) || glm::any(glm::greaterThan(inside, glm::vec2(0.98f)))) {
        continue;
      }
      const glm::ivec2 texel = glm::min(glm::ivec2(at), glm::ivec2(static_cast<int>(resolution) - 1));
      const glm::vec4 value = evaluate(size_t(texel.y) * resolution + size_t(texel.x), view, light);
      // Premultiplied by alpha (cloth.glsl), over the black background.
      const glm::vec3 expected = 1.5f * glm::vec3(value) * value.a;
      for (int c = 0; c < 3; ++c) {
        const double error = std::abs(frame.image.at(x, y, c) - expected[c]) / std::max(expected[c], 1e-3f);
        probe.worst = std::max(probe.worst, error);
      }
      ++probe.compared;
    }
  }
  return probe;
}

}  // namespace loom
