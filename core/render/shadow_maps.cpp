#include "core/render/shadow_maps.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>

namespace loom {

ShadowMaps::ShadowMaps(int size)
    : size_(size),
      opaque_program_(gl::ShaderProgram::FromEmbedded("shadow_depth")),
      cloth_program_(gl::ShaderProgram::FromEmbedded("scene.vert", "shadow_cloth.frag")) {
  glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &texture_);
  glTextureStorage3D(texture_, 1, GL_DEPTH_COMPONENT32F, size_, size_, kMaxShadowMaps);
  glTextureParameteri(texture_, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTextureParameteri(texture_, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(texture_, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(texture_, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glTextureParameteri(texture_, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
  glTextureParameteri(texture_, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
  glCreateFramebuffers(1, &framebuffer_);
}

ShadowMaps::~ShadowMaps() {
  glDeleteFramebuffers(1, &framebuffer_);
  glDeleteTextures(1, &texture_);
}

void ShadowMaps::Render(const std::vector<glm::vec3>& directions, const SceneBounds& bounds,
                        const std::vector<const gl::MeshBuffer*>& opaque, const std::vector<ClothCaster>& cloth,
                        int fabric_unit) {
  matrices_.clear();
  const float r = bounds.radius;
  // Three map texels of offset: enough for PCF on oblique surfaces, small against the scene.
  bias_ = 3.0f * 2.0f * r / static_cast<float>(size_);
  // Maps [-1,1] clip space to [0,1] texture space and depth.
  const glm::mat4 to_texture = glm::translate(glm::mat4(1.0f), glm::vec3(0.5f)) * glm::scale(glm::mat4(1.0f), glm::vec3(0.5f));

  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  glViewport(0, 0, size_, size_);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  for (size_t layer = 0; layer < directions.size() && layer < kMaxShadowMaps; ++layer) {
    const glm::vec3 d = glm::normalize(directions[layer]);
    const glm::vec3 up = std::abs(d.z) < 0.99f ? glm::vec3(0, 0, 1) : glm::vec3(1, 0, 0);
    const glm::mat4 view = glm::lookAt(bounds.centre + d * (2.0f * r), bounds.centre, up);
    const glm::mat4 projection = glm::ortho(-r, r, -r, r, 0.0f, 4.0f * r);
    const glm::mat4 view_projection = projection * view;
    matrices_.push_back(to_texture * view_projection);

    glNamedFramebufferTextureLayer(framebuffer_, GL_DEPTH_ATTACHMENT, texture_, 0, static_cast<GLint>(layer));
    glNamedFramebufferDrawBuffer(framebuffer_, GL_NONE);
    glClear(GL_DEPTH_BUFFER_BIT);
    opaque_program_.Use();
    opaque_program_.Set("u_light_view_projection", view_projection);
    for (const gl::MeshBuffer* caster : opaque) caster->Draw();
    cloth_program_.Use();
    cloth_program_.Set("u_view_projection", view_projection);
    cloth_program_.Set("u_towards_light", d);
    for (size_t i = 0; i < cloth.size(); ++i) {
      cloth[i].fabric->Bind(cloth_program_, fabric_unit, cloth[i].repeat);
      cloth_program_.Set("u_dither_seed", static_cast<int>(i));
      cloth[i].mesh->Draw();
    }
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

}  // namespace loom
