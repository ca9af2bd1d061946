#include "core/gl/layer_texture.h"

#include <algorithm>

namespace loom::gl {

LayerTexture::LayerTexture(GLenum format, int size, bool depth_compare)
    : format_(format), size_(size), depth_compare_(depth_compare) {}

LayerTexture::~LayerTexture() { glDeleteTextures(1, &texture_); }

void LayerTexture::Reserve(int layers) {
  layers = std::max(layers, 1);
  if (layers <= layers_) return;
  glDeleteTextures(1, &texture_);
  glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &texture_);
  glTextureStorage3D(texture_, 1, format_, size_, size_, layers);
  glTextureParameteri(texture_, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTextureParameteri(texture_, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(texture_, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(texture_, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  if (depth_compare_) {
    glTextureParameteri(texture_, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    glTextureParameteri(texture_, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
  }
  layers_ = layers;
}

}  // namespace loom::gl
