#pragma once
// An offscreen float render target: RGBA32F colour and 24-bit depth, optionally
// multisampled. Reading back resolves MSAA into a single-sample copy and returns
// linear radiance, top row first.

#include <GL/glcorearb.h>

#include "core/image/image.h"

namespace loom::gl {

class Framebuffer {
 public:
  // samples = 1 for no MSAA, at most MaxSamples(). Throws Error(kInternal) if the
  // FBO is incomplete.
  Framebuffer(int width, int height, int samples = 1);

  // The most MSAA samples this GL gives both attachments (RGBA32F colour, 24-bit
  // depth): GL_MAX_SAMPLES bounded by each format's own limit (llvmpipe: 4).
  // Needs a current context.
  static int MaxSamples();
  ~Framebuffer();
  Framebuffer(const Framebuffer&) = delete;
  Framebuffer& operator=(const Framebuffer&) = delete;

  // Binds for drawing and sets the viewport to the whole target.
  void Bind() const;
  // RGBA float pixels, top row first.
  Image ReadPixels() const;

  int width() const { return width_; }
  int height() const { return height_; }
  int samples() const { return samples_; }

 private:
  struct Target {
    GLuint framebuffer = 0;
    GLuint colour = 0;
    GLuint depth = 0;
  };
  static Target MakeTarget(int width, int height, int samples, bool with_depth);
  static void Destroy(Target& target);

  int width_, height_, samples_;
  Target draw_;
  Target resolve_;  // only when multisampled
};

}  // namespace loom::gl
