#include "core/render/shadow_maps.h"

#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>

namespace loom {
namespace {

// Maps [-1,1] clip space to [0,1] texture space and depth.
const glm::mat4 kToTexture = glm::translate(glm::mat4(1.0f), glm::vec3(0.5f)) * glm::scale(glm::mat4(1.0f), glm::vec3(0.5f));
// Three map texels of offset: enough for PCF on oblique surfaces, small against the scene.
constexpr float kBiasTexels = 3.0f;

// A layer's view and projection.
struct LayerView {
  glm::mat4 view_projection;
  float map_scale;  // 0.5 · projection[0][0]
};

// A directional light's orthographic view over `bounds`.
LayerView DirectionalView(glm::vec3 towards_light, const SceneBounds& bounds) {
  const float r = bounds.radius;
  const glm::vec3 d = glm::normalize(towards_light);
  const glm::vec3 up = std::abs(d.z) < 0.99f ? glm::vec3(0, 0, 1) : glm::vec3(1, 0, 0);
  const glm::mat4 view = glm::lookAt(bounds.centre + d * (2.0f * r), bounds.centre, up);
  const glm::mat4 projection = glm::ortho(-r, r, -r, r, 0.0f, 4.0f * r);
  return {projection * view, 0.5f * projection[0][0]};
}

// Cube face `face` (+x, −x, +y, −y, +z, −z) of a point light at `position`, deep
// enough for `bounds`.
LayerView PointFaceView(glm::vec3 position, int face, const SceneBounds& bounds) {
  glm::vec3 axis(0.0f);
  axis[face / 2] = face % 2 == 0 ? 1.0f : -1.0f;
  const glm::vec3 up = face / 2 == 2 ? glm::vec3(0, 1, 0) : glm::vec3(0, 0, 1);
  const float distance = glm::length(position - bounds.centre);
  const float far = distance + bounds.radius;
  const float near = std::max(distance - bounds.radius, 1e-3f * far);
  const glm::mat4 projection = glm::perspective(0.5f * glm::pi<float>(), 1.0f, near, far);
  return {projection * glm::lookAt(position, position + axis, up), 0.5f * projection[0][0]};
}

}  // namespace

ShadowMaps::ShadowMaps(int size)
    : texture_(GL_DEPTH_COMPONENT32F, size, true),
      opaque_program_(gl::ShaderProgram::FromEmbedded("shadow_depth")),
      cloth_program_(gl::ShaderProgram::FromEmbedded("scene.vert", "shadow_cloth.frag")) {
  glCreateFramebuffers(1, &framebuffer_);
}

ShadowMaps::~ShadowMaps() {
  glDeleteFramebuffers(1, &framebuffer_);
}

void ShadowMaps::Render(const std::vector<ShadowLight>& lights, const SceneBounds& bounds,
                        const std::vector<const gl::MeshBuffer*>& opaque, const std::vector<ClothCaster>& cloth,
                        int fabric_unit) {
  std::vector<LayerView> views;
  std::vector<glm::vec4> light_of_layer;
  first_layers_.clear();
  for (size_t k = 0; k < lights.size() && k < kMaxShadowMaps; ++k) {
    first_layers_.push_back(static_cast<int>(views.size()));
    if (lights[k].directional) {
      views.push_back(DirectionalView(lights[k].vector, bounds));
      light_of_layer.emplace_back(glm::normalize(lights[k].vector), 0.0f);
    } else {
      for (int face = 0; face < kPointShadowFaces; ++face) {
        views.push_back(PointFaceView(lights[k].vector, face, bounds));
        light_of_layer.emplace_back(lights[k].vector, 1.0f);
      }
    }
  }
  matrices_.clear();
  map_scales_.clear();
  for (const LayerView& v : views) {
    matrices_.push_back(kToTexture * v.view_projection);
    map_scales_.push_back(v.map_scale);
  }
  bias_ = kBiasTexels * 2.0f * bounds.radius / static_cast<float>(size());
  point_bias_ = kBiasTexels * 2.0f / static_cast<float>(size());  // a 90° face's texel at distance 1

  texture_.Reserve(static_cast<int>(views.size()));

  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  glViewport(0, 0, size(), size());
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  for (size_t layer = 0; layer < views.size(); ++layer) {
    const glm::mat4& view_projection = views[layer].view_projection;
    glNamedFramebufferTextureLayer(framebuffer_, GL_DEPTH_ATTACHMENT, texture_.id(), 0, static_cast<GLint>(layer));
    glNamedFramebufferDrawBuffer(framebuffer_, GL_NONE);
    glClear(GL_DEPTH_BUFFER_BIT);
    opaque_program_.Use();
    opaque_program_.Set("u_light_view_projection", view_projection);
    for (const gl::MeshBuffer* caster : opaque) caster->Draw();
    cloth_program_.Use();
    cloth_program_.Set("u_view_projection", view_projection);
    cloth_program_.Set("u_light", light_of_layer[layer]);
    for (size_t i = 0; i < cloth.size(); ++i) {
      cloth[i].fabric->Bind(cloth_program_, fabric_unit, cloth[i].repeat);
      cloth_program_.Set("u_dither_seed", static_cast<int>(i));
      cloth[i].mesh->Draw();
    }
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

}  // namespace loom
