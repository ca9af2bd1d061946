#include "core/render/scene_lights.h"

#include <algorithm>
#include <string>

#include <spdlog/spdlog.h>

#include "core/scene/scene_light.h"

namespace loom {

SceneBounds SceneBoundsOf(const std::vector<SceneMesh>& meshes) {
  const Bounds bounds = SceneGeometryBounds(meshes);
  return {bounds.centre(), std::max(0.5f * bounds.diagonal(), 1e-3f)};
}

void SetUpLights(const v1::SceneSpec& scene, const SceneBounds& bounds,
                 const std::vector<const gl::MeshBuffer*>& opaque_casters,
                 const std::vector<ShadowMaps::ClothCaster>& cloth_casters, ShadowMaps& shadows, int fabric_unit,
                 const std::vector<const gl::ShaderProgram*>& programs) {
  const bool casters = !opaque_casters.empty() || !cloth_casters.empty();
  std::vector<ShadowLight> shadow_lights;
  std::vector<int> shadow_of_light;  // per light its index in shadow_lights, or −1
  const int count = std::min(scene.lights_size(), kMaxLights);
  std::vector<SceneLight> lights;
  for (int i = 0; i < count; ++i) {
    lights.push_back(MakeSceneLight(scene.lights(i)));
    const SceneLight& light = lights.back();
    const bool shadowed = casters && light.casts_shadows && shadow_lights.size() < kMaxShadowMaps;
    if (casters && light.casts_shadows && !shadowed) {
      spdlog::warn("scene.lights[{}].casts_shadows: only the first {} shadow-casting lights cast shadows; this one casts none",
                   i, kMaxShadowMaps);
    }
    shadow_of_light.push_back(shadowed ? static_cast<int>(shadow_lights.size()) : -1);
    if (shadowed) shadow_lights.push_back({light.vector, light.directional});
  }
  shadows.Render(shadow_lights, bounds, opaque_casters, cloth_casters, fabric_unit);
  for (const gl::ShaderProgram* program : programs) {
    program->Set("u_light_count", count);
    for (int i = 0; i < count; ++i) {
      const SceneLight& light = lights[static_cast<size_t>(i)];
      const int shadow = shadow_of_light[static_cast<size_t>(i)];
      program->Set("u_light_vector", i, glm::vec4(light.vector, light.directional ? 0.0f : 1.0f));
      program->Set("u_light_radiance", i, light.radiance);
      program->Set("u_light_shadow", i, shadow < 0 ? -1 : shadows.first_layer(static_cast<size_t>(shadow)));
    }
    for (int layer = 0; layer < shadows.layer_count(); ++layer) {
      program->Set("u_shadow_matrix", layer, shadows.matrix(layer));
    }
    program->Set("u_shadow_bias", shadows.bias());
    program->Set("u_shadow_point_bias", shadows.point_bias());
  }
}

}  // namespace loom
