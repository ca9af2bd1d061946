#include "core/render/scene_lights.h"

#include <algorithm>
#include <string>

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
  std::vector<glm::vec3> shadow_directions;
  const int count = std::min(scene.lights_size(), kMaxLights);
  for (int i = 0; i < count; ++i) {
    const SceneLight light = MakeSceneLight(scene.lights(i));
    int shadow = -1;
    if (casters && light.directional && light.casts_shadows && shadow_directions.size() < kMaxShadowMaps) {
      shadow = static_cast<int>(shadow_directions.size());
      shadow_directions.push_back(light.vector);
    }
    for (const gl::ShaderProgram* program : programs) {
      program->Set("u_light_vector", i, glm::vec4(light.vector, light.directional ? 0.0f : 1.0f));
      program->Set("u_light_radiance", i, light.radiance);
      program->Set("u_light_shadow", i, shadow);
    }
  }
  shadows.Render(shadow_directions, bounds, opaque_casters, cloth_casters, fabric_unit);
  for (const gl::ShaderProgram* program : programs) {
    program->Set("u_light_count", count);
    for (size_t layer = 0; layer < shadow_directions.size(); ++layer) {
      program->Set("u_shadow_matrix", static_cast<int>(layer), shadows.matrix(static_cast<int>(layer)));
    }
    program->Set("u_shadow_bias", shadows.bias());
  }
}

}  // namespace loom
