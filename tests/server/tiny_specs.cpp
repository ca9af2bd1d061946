#include "tests/server/tiny_specs.h"

#include "core/methods/asset_pictures.h"
#include "core/spec/spec_math.h"

namespace loom::server {

v1::PrecomputeSettings TinySettings() {
  v1::PrecomputeSettings settings;
  settings.set_spatial_resolution(8);
  settings.set_view_directions(16);
  settings.set_light_directions(16);
  settings.set_lobes(1);
  settings.set_indirect_bounces(0);
  settings.set_supersampling(1);
  return settings;
}

v1::FabricSpec KnitFabric() {
  v1::FabricSpec fabric;
  fabric.mutable_knit();
  return fabric;
}

v1::SceneSpec TinyScene(uint32_t width, uint32_t height) {
  v1::SceneSpec scene;
  scene.set_name("tiny knit plane");
  v1::SceneObject& cloth = *scene.add_objects();
  cloth.set_name("cloth");
  cloth.mutable_mesh()->set_builtin(v1::BUILTIN_SHAPE_PLANE);
  *cloth.mutable_fabric()->mutable_fabric() = KnitFabric();
  *cloth.mutable_fabric()->mutable_precompute() = TinySettings();
  cloth.mutable_fabric()->set_repeat_u(4);
  cloth.mutable_fabric()->set_repeat_v(4);
  v1::Camera& camera = *scene.mutable_camera();
  *camera.mutable_position() = ToVec3({0.0f, -1.5f, 1.5f});
  v1::Light& light = *scene.add_lights();
  *light.mutable_direction() = ToVec3({-0.3f, -0.5f, 1.0f});
  light.set_intensity(3.0f);
  light.set_casts_shadows(true);
  v1::RenderSettings& render = *scene.mutable_render();
  render.set_width(width);
  render.set_height(height);
  render.set_msaa_samples(1);
  render.set_shadow_map_size(256);
  render.set_format(v1::IMAGE_FORMAT_EXR);
  return scene;
}

std::set<std::string> TinyPrecomputeFiles() {
  std::set<std::string> files{"lut.exr", "manifest.json", "parameters.exr", "preview.png", kAssetPicturesFile};
  for (uint32_t level = 0; level < 4; ++level) {
    for (const char* map : {"albedo", "lobe1", "lut", "alpha"}) files.insert(AssetPictureFile(level, map));
  }
  return files;
}

v1::SubmitJobRequest PrecomputeRequest() {
  v1::SubmitJobRequest request;
  *request.mutable_precompute()->mutable_fabric() = KnitFabric();
  *request.mutable_precompute()->mutable_settings() = TinySettings();
  return request;
}

v1::SubmitJobRequest RenderRequest(const v1::SceneSpec& scene) {
  v1::SubmitJobRequest request;
  *request.mutable_render()->mutable_scene() = scene;
  return request;
}

}  // namespace loom::server
