#pragma once
// A 2-D array texture of square layers, linearly filtered and clamped to the edge,
// that grows to the layers asked of it: the shadow maps' depth layers and the yarn
// shadow map's beside them, whose count follows the scene's lights. Growing makes a
// new texture (id() changes, the contents are lost); it never shrinks.

#include <GL/glcorearb.h>

namespace loom::gl {

class LayerTexture {
 public:
  // `format` a sized internal format; `depth_compare`: sampled as a shadow texture
  // (GL_LEQUAL against the reference depth).
  LayerTexture(GLenum format, int size, bool depth_compare);
  ~LayerTexture();
  LayerTexture(const LayerTexture&) = delete;
  LayerTexture& operator=(const LayerTexture&) = delete;

  // At least max(layers, 1) layers from now on. Needs a current context.
  void Reserve(int layers);

  GLuint id() const { return texture_; }
  int size() const { return size_; }

 private:
  GLenum format_;
  int size_;
  bool depth_compare_;
  int layers_ = 0;
  GLuint texture_ = 0;
};

}  // namespace loom::gl
