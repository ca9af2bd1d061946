#pragma once
// What the compute shading pass (render.shading_pass COMPUTE; GpuRenderer) keeps
// per pixel between its passes over a cloth: the G-buffers of the cloth's two
// nearest layers (one sample a pixel, each five RGBA32F attachments and a depth
// buffer, the second peeled behind the first; their contents: core/shaders/cloth.glsl),
// the shadings the compute pass writes of each, and a counter of the fragments the
// composite pass had to shade in place. Needs a current context.

#include <GL/glcorearb.h>

#include <array>
#include <cstdint>

namespace loom {

class ClothGbuffer {
 public:
  static constexpr int kLayers = 2;       // the nearest cloth surfaces a pixel keeps
  static constexpr int kAttachments = 5;  // per layer

  // Throws Error(kInternal) if a framebuffer is incomplete.
  ClothGbuffer(int width, int height);
  ~ClothGbuffer();
  ClothGbuffer(const ClothGbuffer&) = delete;
  ClothGbuffer& operator=(const ClothGbuffer&) = delete;

  // Binds layer `layer`'s G-buffer for drawing, its viewport the whole of it, and
  // clears it: no cloth anywhere (attachment 0's w −1), depth 1. For the second
  // layer, binds the first's attachment 0 to image unit 0 (cloth.glsl u_nearer).
  void BindAndClear(int layer) const;
  // For the compute pass over `layer`: its attachments to image units 0–4, its
  // shadings to unit 5.
  void BindForCompute(int layer) const;
  // For the composite: each layer's attachment 0 to units 0 and 1, its shadings to
  // units 2 and 3, the counter to atomic counter binding 0.
  void BindForComposite() const;
  // Groups of 8×8 for a compute dispatch over every pixel.
  void Dispatch() const;
  void ResetCounter() const;
  uint32_t Counter() const;  // waits for the GPU

  int width() const { return width_; }
  int height() const { return height_; }

 private:
  struct Layer {
    GLuint framebuffer = 0, depth = 0, shaded = 0;
    std::array<GLuint, kAttachments> attachments{};
  };
  void Destroy();

  int width_, height_;
  std::array<Layer, kLayers> layers_{};
  GLuint counter_ = 0;
};

}  // namespace loom
