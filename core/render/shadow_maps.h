#pragma once
// Macro-scale shadows (Daubert's fitted BRDFs hold the yarn-scale shadowing; the
// shadows of cloth on cloth and on other objects come from here): depth maps of the
// shadow-casting lights in one 2-D array texture, sampled with hardware depth
// comparison and 3×3 PCF in core/shaders/lights.glsl. A directional light has one
// orthographic layer over the scene; a point light six perspective layers, the faces
// of a cube about it (+x, −x, +y, −y, +z, −z; lights.glsl picks the face by the major
// axis from the light). Cloth lets light through its holes: it writes depth on the
// fraction of map texels its coverage for the light's direction says
// (core/shaders/shadow_cloth.frag).

#include <GL/glcorearb.h>

#include <glm/glm.hpp>
#include <vector>

#include "core/gl/layer_texture.h"
#include "core/gl/mesh_buffer.h"
#include "core/gl/shader_program.h"
#include "core/methods/fabric_method.h"

namespace loom {

inline constexpr int kMaxShadowMaps = 4;   // shadow-casting lights, as in lights.glsl
inline constexpr int kPointShadowFaces = 6;

struct SceneBounds {
  glm::vec3 centre{0.0f};
  float radius = 1.0f;
};

// A light that casts shadows: a unit direction towards it, or its position.
struct ShadowLight {
  glm::vec3 vector{0.0f};
  bool directional = true;
};

class ShadowMaps {
 public:
  explicit ShadowMaps(int size);
  ~ShadowMaps();
  ShadowMaps(const ShadowMaps&) = delete;
  ShadowMaps& operator=(const ShadowMaps&) = delete;

  // A mesh with a fabric of any method, repeated `repeat` times across its uv square.
  struct ClothCaster {
    const gl::MeshBuffer* mesh;
    const GpuFabric* fabric;
    glm::vec2 repeat;
  };

  // Renders the layers of `lights` (at most kMaxShadowMaps), light k's from
  // first_layer(k) on, covering `bounds`; matrix(i) maps world space to layer i's
  // [0,1]³. Cloth binds its fabric's textures to units from `fabric_unit` on. The
  // texture grows to the layers asked for (texture() may change).
  void Render(const std::vector<ShadowLight>& lights, const SceneBounds& bounds,
              const std::vector<const gl::MeshBuffer*>& opaque, const std::vector<ClothCaster>& cloth,
              int fabric_unit);

  GLuint texture() const { return texture_.id(); }
  int first_layer(size_t light) const { return first_layers_[light]; }
  int layer_count() const { return static_cast<int>(matrices_.size()); }
  const glm::mat4& matrix(int layer) const { return matrices_[static_cast<size_t>(layer)]; }
  // Map units per world unit across the light's view at w = 1 of matrix(layer)'s clip
  // space (w the depth from a point light; 1 for a directional one).
  float map_scale(int layer) const { return map_scales_[static_cast<size_t>(layer)]; }
  int size() const { return texture_.size(); }
  // World-space offset along the normal that keeps a lit surface from shadowing
  // itself: bias() for a directional light's layer, point_bias() × the distance from
  // a point light.
  float bias() const { return bias_; }
  float point_bias() const { return point_bias_; }

 private:
  gl::LayerTexture texture_;
  GLuint framebuffer_ = 0;
  gl::ShaderProgram opaque_program_;
  gl::ShaderProgram cloth_program_;
  std::vector<int> first_layers_;
  std::vector<glm::mat4> matrices_;
  std::vector<float> map_scales_;
  float bias_ = 0.0f, point_bias_ = 0.0f;
};

}  // namespace loom
