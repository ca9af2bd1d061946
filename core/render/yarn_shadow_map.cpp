#include "core/render/yarn_shadow_map.h"

#include "core/util/error.h"

namespace loom {

YarnShadowMap::YarnShadowMap(int size)
    : texture_(GL_RGBA16F, size, false), program_(gl::ShaderProgram::FromEmbedded("yarn_shadow_map.vert", "yarn_shadow_map.frag")) {
  glCreateFramebuffers(1, &framebuffer_);
  glCreateVertexArrays(1, &vao_);
}

YarnShadowMap::~YarnShadowMap() {
  glDeleteVertexArrays(1, &vao_);
  glDeleteFramebuffers(1, &framebuffer_);
  glDeleteTextures(1, &profiles_);
}

void YarnShadowMap::Render(const ShadowMaps& shadows, const std::vector<const Lumislice*>& yarns,
                           const std::function<void(const DrawBatch& draw)>& for_each_batch) {
  const int layers = shadows.layer_count();
  texture_.Reserve(layers);
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  glViewport(0, 0, size(), size());
  const GLfloat clear[4] = {1.0f, 1.0f, 1.0f, 1.0f};
  for (int layer = 0; layer < layers; ++layer) {
    glNamedFramebufferTextureLayer(framebuffer_, GL_COLOR_ATTACHMENT0, texture_.id(), 0, layer);
    glClearNamedFramebufferfv(framebuffer_, GL_COLOR, 0, clear);
  }
  if (layers == 0 || yarns.empty()) return;
  std::vector<float> profiles;
  for (const Lumislice* yarn : yarns) profiles.insert(profiles.end(), yarn->shadow_profile.begin(), yarn->shadow_profile.end());
  glDeleteTextures(1, &profiles_);
  glCreateTextures(GL_TEXTURE_2D, 1, &profiles_);
  glTextureStorage2D(profiles_, 1, GL_R32F, kYarnShadowProfileSamples, static_cast<GLsizei>(yarns.size()));
  glTextureSubImage2D(profiles_, 0, 0, 0, kYarnShadowProfileSamples, static_cast<GLsizei>(yarns.size()), GL_RED,
                      GL_FLOAT, profiles.data());
  glTextureParameteri(profiles_, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTextureParameteri(profiles_, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(profiles_, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(profiles_, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);

  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  glEnable(GL_BLEND);
  glBlendEquationSeparate(GL_FUNC_ADD, GL_MIN);
  glBlendFuncSeparate(GL_ZERO, GL_SRC_COLOR, GL_ONE, GL_ONE);
  program_.Use();
  glBindTextureUnit(0, profiles_);
  program_.Set("u_profiles", 0);
  program_.Set("u_texel", 1.0f / static_cast<float>(size()));
  for (size_t i = 0; i < yarns.size(); ++i) program_.Set("u_extent", static_cast<int>(i), yarns[i]->section.extent());
  glBindVertexArray(vao_);
  for (int layer = 0; layer < layers; ++layer) {
    glNamedFramebufferTextureLayer(framebuffer_, GL_COLOR_ATTACHMENT0, texture_.id(), 0, layer);
    if (glCheckNamedFramebufferStatus(framebuffer_, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
      throw Error(ErrorCode::kInternal, "yarn shadow map: framebuffer incomplete");
    }
    program_.Set("u_light_matrix", shadows.matrix(layer));
    program_.Set("u_map_scale", shadows.map_scale(layer));
    for_each_batch([](GLsizei count) { glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, count); });
  }
  glBindVertexArray(0);
  glBlendEquation(GL_FUNC_ADD);
  glDisable(GL_BLEND);
}

}  // namespace loom
