#include "core/render/cloth_gbuffer.h"

#include <string>

#include "core/util/error.h"

namespace loom {

ClothGbuffer::ClothGbuffer(int width, int height) : width_(width), height_(height) {
  for (Layer& layer : layers_) {
    glCreateFramebuffers(1, &layer.framebuffer);
    glCreateTextures(GL_TEXTURE_2D, kAttachments, layer.attachments.data());
    std::array<GLenum, kAttachments> buffers{};
    for (int i = 0; i < kAttachments; ++i) {
      glTextureStorage2D(layer.attachments[i], 1, GL_RGBA32F, width, height);
      glNamedFramebufferTexture(layer.framebuffer, GL_COLOR_ATTACHMENT0 + i, layer.attachments[i], 0);
      buffers[i] = GL_COLOR_ATTACHMENT0 + i;
    }
    glNamedFramebufferDrawBuffers(layer.framebuffer, kAttachments, buffers.data());
    glCreateRenderbuffers(1, &layer.depth);
    glNamedRenderbufferStorage(layer.depth, GL_DEPTH_COMPONENT32F, width, height);
    glNamedFramebufferRenderbuffer(layer.framebuffer, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, layer.depth);
    glCreateTextures(GL_TEXTURE_2D, 1, &layer.shaded);
    glTextureStorage2D(layer.shaded, 1, GL_RGBA32F, width, height);
    const GLenum status = glCheckNamedFramebufferStatus(layer.framebuffer, GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
      Destroy();
      throw Error(ErrorCode::kInternal, "cloth G-buffer " + std::to_string(width) + "x" + std::to_string(height) +
                                            " is incomplete (status 0x" + std::to_string(status) + ")");
    }
  }
  glCreateBuffers(1, &counter_);
  glNamedBufferStorage(counter_, sizeof(uint32_t), nullptr, GL_DYNAMIC_STORAGE_BIT);
}

ClothGbuffer::~ClothGbuffer() { Destroy(); }

void ClothGbuffer::Destroy() {
  for (Layer& layer : layers_) {
    glDeleteTextures(1, &layer.shaded);
    glDeleteRenderbuffers(1, &layer.depth);
    glDeleteTextures(kAttachments, layer.attachments.data());
    glDeleteFramebuffers(1, &layer.framebuffer);
    layer = Layer{};
  }
  glDeleteBuffers(1, &counter_);
  counter_ = 0;
}

void ClothGbuffer::BindAndClear(int layer) const {
  const Layer& target = layers_[layer];
  glBindFramebuffer(GL_FRAMEBUFFER, target.framebuffer);
  glViewport(0, 0, width_, height_);
  const float none[4] = {0.0f, 0.0f, 0.0f, -1.0f};
  for (int i = 0; i < kAttachments; ++i) glClearNamedFramebufferfv(target.framebuffer, GL_COLOR, i, none);
  const float far = 1.0f;
  glClearNamedFramebufferfv(target.framebuffer, GL_DEPTH, 0, &far);
  if (layer > 0) {
    glBindImageTexture(0, layers_[layer - 1].attachments[0], 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
  }
}

void ClothGbuffer::BindForCompute(int layer) const {
  const Layer& source = layers_[layer];
  for (int i = 0; i < kAttachments; ++i) {
    glBindImageTexture(i, source.attachments[i], 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
  }
  glBindImageTexture(kAttachments, source.shaded, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
}

void ClothGbuffer::BindForComposite() const {
  for (int k = 0; k < kLayers; ++k) {
    glBindImageTexture(k, layers_[k].attachments[0], 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    glBindImageTexture(kLayers + k, layers_[k].shaded, 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
  }
  glBindBufferBase(GL_ATOMIC_COUNTER_BUFFER, 0, counter_);
}

void ClothGbuffer::Dispatch() const { glDispatchCompute((width_ + 7) / 8, (height_ + 7) / 8, 1); }

void ClothGbuffer::ResetCounter() const {
  const uint32_t zero = 0;
  glNamedBufferSubData(counter_, 0, sizeof(zero), &zero);
}

uint32_t ClothGbuffer::Counter() const {
  uint32_t count = 0;
  glGetNamedBufferSubData(counter_, 0, sizeof(count), &count);
  return count;
}

}  // namespace loom
