#include "core/methods/level_texture.h"

namespace loom {

LevelTexture::LevelTexture(int levels, int side0, int channels, bool half, int layers)
    : side0_(side0), channels_(channels), array_(layers > 0) {
  const GLenum format = channels == 4   ? (half ? GL_RGBA16F : GL_RGBA32F)
                        : channels == 3 ? (half ? GL_RGB16F : GL_RGB32F)
                                        : (half ? GL_R16F : GL_R32F);
  glCreateTextures(array_ ? GL_TEXTURE_2D_ARRAY : GL_TEXTURE_2D, 1, &texture_);
  if (array_) {
    glTextureStorage3D(texture_, levels, format, side0, side0, layers);
  } else {
    glTextureStorage2D(texture_, levels, format, side0, side0);
  }
  glTextureParameteri(texture_, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_NEAREST);
  glTextureParameteri(texture_, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(texture_, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(texture_, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glTextureParameteri(texture_, GL_TEXTURE_MAX_LEVEL, levels - 1);
}

LevelTexture::~LevelTexture() { glDeleteTextures(1, &texture_); }

void LevelTexture::Upload(int level, const float* pixels, int layer) const {
  const int side = side0_ >> level;
  const GLenum format = channels_ == 4 ? GL_RGBA : channels_ == 3 ? GL_RGB : GL_RED;
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  if (array_) {
    glTextureSubImage3D(texture_, level, 0, 0, layer, side, side, 1, format, GL_FLOAT, pixels);
  } else {
    glTextureSubImage2D(texture_, level, 0, 0, side, side, format, GL_FLOAT, pixels);
  }
}

}  // namespace loom
