#include "tests/core/render/comparison_scene.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>

#include "core/gl/egl_context.h"
#include "core/precompute/fabric_precompute.h"
#include "core/render/reference_renderer.h"
#include "core/render/scene_render.h"
#include "core/methods/svbrdf/svbrdf_method.h"
#include "core/render/gpu_renderer.h"
#include "core/spec/defaults.h"
#include "core/spec/fabric_key.h"
#include "core/spec/spec_json.h"
#include "core/spec/validate.h"

namespace loom::testing {

v1::SceneSpec MakeComparisonScene(const ComparisonOptions& o) {
  constexpr float kPi = 3.14159265f;
  const float t = o.tilt_degrees * kPi / 180.0f;
  // Behind the plane's near edge at any tilt, so none of it is clipped; far covers its far edge.
  const float distance = std::max(5.0f, o.plane_length);
  const float dy = -distance * std::sin(t), dz = distance * std::cos(t);
  const float fov = 2.0f * std::atan(0.5f * o.view_height / distance) * 180.0f / kPi;
  const auto str = [](float v) { return std::to_string(v); };
  const std::string floor = o.red_floor ? R"(, {"mesh": {"builtin": "BUILTIN_SHAPE_PLANE"},
      "transform": {"translation": {"z": -0.5}, "scale": {"x": )" + str(3 * o.plane_width) + R"(, "y": )" +
                                              str(3 * o.plane_length) + R"(, "z": 1}},
      "base_colour": {"r": 1, "g": 0, "b": 0}})"
                                        : "";
  const std::string x = str(o.camera_shift);
  const std::string json = R"({"objects": [{"mesh": )" + o.mesh + R"(,
      "transform": {"scale": {"x": )" + str(o.plane_width) + R"(, "y": )" + str(o.plane_length) + R"(, "z": 1}},
      "fabric": {"fabric": )" + o.fabric + R"(, "precompute": )" + o.precompute + R"(, "repeat_u": )" +
                           str(o.repeat) + R"(, "repeat_v": )" + str(o.repeat * o.plane_length / o.plane_width) +
                           "}}" + floor + R"(],
    "camera": {"projection": ")" + (o.perspective ? "PROJECTION_PERSPECTIVE" : "PROJECTION_ORTHOGRAPHIC") +
                           R"(", "ortho_height": )" + str(o.view_height) + R"(, "fov_y_degrees": )" + str(fov) +
                           R"(, "up": {"x": 0, "y": 1, "z": 0}, "far": )" + str(4 * distance) + R"(,
               "position": {"x": )" + x + R"(, "y": )" + str(dy) + R"(, "z": )" + str(dz) +
                           R"(}, "target": {"x": )" + x + R"(, "y": 0, "z": 0}},
    "lights": [{"direction": )" + o.light + R"(, "intensity": 3, "casts_shadows": )" +
                           (o.shadows ? "true" : "false") + R"(}],
    "render": {"width": )" + std::to_string(o.size) + R"(, "height": )" + std::to_string(o.size) +
                           R"(, "msaa_samples": 4, "reference_samples": )" + std::to_string(o.reference_samples) +
                           R"(, "level_mode": ")" + o.level_mode + R"(", "texel_filter": ")" + o.texel_filter +
                           R"("}})";
  v1::SceneSpec scene = WithDefaults(ParseSpecJson<v1::SceneSpec>(json, "scene"));
  ValidateOrThrow(scene);
  return scene;
}

// Each distinct fabric fitted once per test binary.
const SvbrdfAsset& AssetOf(const v1::FabricBinding& binding) {
  static std::map<std::string, std::unique_ptr<SvbrdfAsset>> cache;
  auto& asset = cache[FabricKey(binding.fabric(), binding.precompute())];
  if (!asset) asset = std::make_unique<SvbrdfAsset>(PrecomputeFabric(binding.fabric(), binding.precompute()));
  return *asset;
}

const FittedFabric& FitOf(const v1::FabricBinding& binding) { return AssetOf(binding).fit(); }

Image RenderSvbrdf(const v1::SceneSpec& scene, const MeshTextResolver& resolve) {
  static const auto context = gl::EglContext::Create();
  static GpuRenderer renderer(*context);
  const auto meshes = BuildSceneGeometry(scene, resolve);
  FabricAssets assets;
  for (const v1::SceneObject& object : scene.objects()) {
    if (!object.has_fabric()) continue;
    assets[FabricKey(object.fabric().fabric(), object.fabric().precompute())] = &AssetOf(object.fabric());
  }
  return RenderScene(renderer, scene, meshes, assets).image;
}

Image RenderReference(const v1::SceneSpec& scene, const MeshTextResolver& resolve) {
  ReferenceRenderer renderer;
  return renderer.Render(scene, BuildSceneGeometry(scene, resolve)).image;
}

double MeanRed(const Image& image) {
  double sum = 0.0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) sum += image.at(x, y, 0);
  return sum / (image.width * image.height);
}

}  // namespace loom::testing
