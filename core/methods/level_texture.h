#pragma once
// A GPU texture whose mip level ℓ is a fabric method's level ℓ (the method's own
// level, not a filtered copy): square, side0 >> ℓ texels a side, RGB or RGBA, half
// or full floats, optionally an array of layers. Filtered linearly inside one level
// (between stored directions of an atlas), clamped at the edges; the shader picks
// levels with textureLod. On the calling thread's current GL context.

#include <GL/glcorearb.h>

namespace loom {

class LevelTexture {
 public:
  // channels 1, 3 or 4; layers = 0: a 2-D texture; otherwise a 2-D array of that
  // many layers.
  LevelTexture(int levels, int side0, int channels, bool half, int layers = 0);
  ~LevelTexture();
  LevelTexture(const LevelTexture&) = delete;
  LevelTexture& operator=(const LevelTexture&) = delete;

  // Level `level` (of layer `layer` for an array): (side0 >> level)² pixels of
  // `channels` floats, row-major.
  void Upload(int level, const float* pixels, int layer = 0) const;
  GLuint id() const { return texture_; }

 private:
  GLuint texture_ = 0;
  int side0_, channels_;
  bool array_;
};

}  // namespace loom
