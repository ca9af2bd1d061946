#include "core/render/fabric_preview.h"

#include "core/render/scene_render.h"
#include "core/spec/defaults.h"
#include "core/spec/spec_math.h"
#include "core/spec/validate.h"

namespace loom {

v1::SceneSpec FabricPreviewScene(const v1::FabricSpec& fabric, const v1::PrecomputeSettings& settings) {
  v1::SceneSpec scene;
  scene.set_name("fabric preview");
  v1::SceneObject& sphere = *scene.add_objects();
  sphere.set_name("sphere");
  sphere.mutable_mesh()->set_builtin(v1::BUILTIN_SHAPE_SPHERE);
  *sphere.mutable_fabric()->mutable_fabric() = fabric;
  *sphere.mutable_fabric()->mutable_precompute() = settings;
  // Longitude runs twice the latitude's length: square tiles at the equator.
  sphere.mutable_fabric()->set_repeat_u(16);
  sphere.mutable_fabric()->set_repeat_v(8);
  v1::Camera& camera = *scene.mutable_camera();
  *camera.mutable_position() = ToVec3({0.0f, -3.4f, 1.0f});
  *camera.mutable_target() = ToVec3({0.0f, 0.0f, 0.0f});
  camera.set_fov_y_degrees(38.0f);
  v1::Light& light = *scene.add_lights();
  *light.mutable_direction() = ToVec3({-0.5f, -0.8f, 0.9f});
  light.set_intensity(3.0f);
  scene.mutable_ambient()->set_r(0.15f);
  scene.mutable_ambient()->set_g(0.15f);
  scene.mutable_ambient()->set_b(0.15f);
  v1::RenderSettings& render = *scene.mutable_render();
  render.set_width(kFabricPreviewPixels);
  render.set_height(kFabricPreviewPixels);
  render.set_format(v1::IMAGE_FORMAT_PNG);
  return scene;
}

Image RenderFabricPreview(GpuRenderer& renderer, const v1::FabricSpec& fabric, const v1::PrecomputeSettings& settings,
                          const FabricAsset& asset) {
  const v1::SceneSpec scene = WithDefaults(FabricPreviewScene(fabric, settings));
  ValidateOrThrow(scene);
  const std::vector<SceneMesh> meshes = BuildSceneGeometry(scene, {});
  const std::vector<SceneFabric> fabrics = SceneFabrics(scene);
  return RenderScene(renderer, scene, meshes, {{fabrics.at(0).key, &asset}}).image;
}

}  // namespace loom
