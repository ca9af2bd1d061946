#pragma once
// The lumislice paper's yarn shadow (§5.2.1, eq. 10) on plain objects: per shadow map
// of core/render/shadow_maps.h, a map in the same light view of the yarn segments'
// centre lines, each drawn as a band of its reach whose texels multiply the light by
// T_y(d) (d the texel's distance from the centre line) and keep the nearest yarn's
// depth. lights.glsl (LOOM_YARN_SHADOWS) dims a receiver farther from the light than
// that depth by the product. The yarn itself takes its shadow from the CPU's
// YarnShadows (core/render/yarn_shadow.h); this map is for what the yarn stands over.

#include <GL/glcorearb.h>

#include <functional>
#include <glm/glm.hpp>
#include <vector>

#include "core/gl/layer_texture.h"
#include "core/gl/shader_program.h"
#include "core/methods/lumislice/lumislice_table.h"
#include "core/render/shadow_maps.h"

namespace loom {

class YarnShadowMap {
 public:
  explicit YarnShadowMap(int size);
  ~YarnShadowMap();
  YarnShadowMap(const YarnShadowMap&) = delete;
  YarnShadowMap& operator=(const YarnShadowMap&) = delete;

  // Draws `draw(count)` for `count` segments now bound (lumislice_segment.glsl).
  using DrawBatch = std::function<void(GLsizei count)>;
  // Renders a layer per layer of `shadows` (its last Render), in that layer's light
  // view. `yarns` are the lumislices of the segments' yarn indices;
  // `for_each_batch(draw)` binds the segments batch by batch, calling draw for each.
  // The texture grows to the layers asked for (texture() may change).
  void Render(const ShadowMaps& shadows, const std::vector<const Lumislice*>& yarns,
              const std::function<void(const DrawBatch& draw)>& for_each_batch);

  GLuint texture() const { return texture_.id(); }
  int size() const { return texture_.size(); }

 private:
  gl::LayerTexture texture_;
  GLuint profiles_ = 0, framebuffer_ = 0, vao_ = 0;
  gl::ShaderProgram program_;
};

}  // namespace loom
