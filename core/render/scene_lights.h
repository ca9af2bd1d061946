#pragma once
// A scene's lights as the GPU renderers' programs see them (core/shaders/lights.glsl):
// the light uniforms, and the macro-scale shadow maps of the lights that cast shadows.

#include <vector>

#include "core/gl/mesh_buffer.h"
#include "core/gl/shader_program.h"
#include "core/render/shadow_maps.h"
#include "core/scene/scene_geometry.h"
#include "core/spec/limits.h"  // kMaxLights, as in lights.glsl
#include "loom/v1/scene.pb.h"

namespace loom {

// What the shadow maps must cover: the meshes' bounding sphere.
SceneBounds SceneBoundsOf(const std::vector<SceneMesh>& meshes);

// Renders the shadow maps the scene's lights need (none when nothing casts) and
// uploads the lights to each of `programs`. Cloth casters bind their fabric's
// textures to units from `fabric_unit` on.
void SetUpLights(const v1::SceneSpec& scene, const SceneBounds& bounds,
                 const std::vector<const gl::MeshBuffer*>& opaque_casters,
                 const std::vector<ShadowMaps::ClothCaster>& cloth_casters, ShadowMaps& shadows, int fabric_unit,
                 const std::vector<const gl::ShaderProgram*>& programs);

}  // namespace loom
