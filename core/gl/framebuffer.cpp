#include "core/gl/framebuffer.h"

#include <algorithm>
#include <string>

#include "core/util/error.h"

namespace loom::gl {

Framebuffer::Target Framebuffer::MakeTarget(int width, int height, int samples, bool with_depth) {
  Target target;
  glCreateFramebuffers(1, &target.framebuffer);
  glCreateRenderbuffers(1, &target.colour);
  if (samples > 1) glNamedRenderbufferStorageMultisample(target.colour, samples, GL_RGBA32F, width, height);
  else glNamedRenderbufferStorage(target.colour, GL_RGBA32F, width, height);
  glNamedFramebufferRenderbuffer(target.framebuffer, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, target.colour);
  if (with_depth) {
    glCreateRenderbuffers(1, &target.depth);
    if (samples > 1) glNamedRenderbufferStorageMultisample(target.depth, samples, GL_DEPTH_COMPONENT24, width, height);
    else glNamedRenderbufferStorage(target.depth, GL_DEPTH_COMPONENT24, width, height);
    glNamedFramebufferRenderbuffer(target.framebuffer, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, target.depth);
  }
  const GLenum status = glCheckNamedFramebufferStatus(target.framebuffer, GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    Destroy(target);
    throw Error(ErrorCode::kInternal, "framebuffer " + std::to_string(width) + "x" + std::to_string(height) +
                                          " with " + std::to_string(samples) +
                                          " samples is incomplete (status 0x" + std::to_string(status) + ")");
  }
  return target;
}

void Framebuffer::Destroy(Target& target) {
  if (target.colour) glDeleteRenderbuffers(1, &target.colour);
  if (target.depth) glDeleteRenderbuffers(1, &target.depth);
  if (target.framebuffer) glDeleteFramebuffers(1, &target.framebuffer);
  target = Target{};
}

int Framebuffer::MaxSamples() {
  GLint limit = 1;
  glGetIntegerv(GL_MAX_SAMPLES, &limit);
  for (const GLenum format : {GLenum{GL_RGBA32F}, GLenum{GL_DEPTH_COMPONENT24}}) {
    // GL_SAMPLES lists the supported counts in descending order: the first is the format's largest.
    GLint largest = 1;
    glGetInternalformativ(GL_RENDERBUFFER, format, GL_SAMPLES, 1, &largest);
    limit = std::min(limit, largest);
  }
  return std::max(limit, 1);
}

Framebuffer::Framebuffer(int width, int height, int samples)
    : width_(width), height_(height), samples_(samples < 1 ? 1 : samples) {
  draw_ = MakeTarget(width_, height_, samples_, /*with_depth=*/true);
  if (samples_ > 1) {
    try {
      resolve_ = MakeTarget(width_, height_, 1, /*with_depth=*/false);
    } catch (...) {
      Destroy(draw_);
      throw;
    }
  }
}

Framebuffer::~Framebuffer() {
  Destroy(draw_);
  Destroy(resolve_);
}

void Framebuffer::Bind() const {
  glBindFramebuffer(GL_FRAMEBUFFER, draw_.framebuffer);
  glViewport(0, 0, width_, height_);
}

Image Framebuffer::ReadPixels() const {
  GLuint source = draw_.framebuffer;
  if (samples_ > 1) {
    glBlitNamedFramebuffer(draw_.framebuffer, resolve_.framebuffer, 0, 0, width_, height_, 0, 0, width_,
                           height_, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    source = resolve_.framebuffer;
  }
  Image bottom_up(width_, height_, 4);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, source);
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width_, height_, GL_RGBA, GL_FLOAT, bottom_up.pixels.data());
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);

  // GL's origin is the bottom-left corner; images are stored top row first.
  return FlippedRows(bottom_up);
}

}  // namespace loom::gl
