#pragma once
// Macro-scale shadows (Daubert's fitted BRDFs hold the yarn-scale shadowing; the
// shadows of cloth on cloth and on other objects come from here): one depth map
// per shadow-casting directional light, in one 2-D array texture, sampled with
// hardware depth comparison and 3×3 PCF in core/shaders/lights.glsl. Cloth lets
// light through its holes: it writes depth on the fraction of map texels its
// coverage for the light's direction says (core/shaders/shadow_cloth.frag). Point
// lights cast no shadows in this renderer.

#include <GL/glcorearb.h>

#include <glm/glm.hpp>
#include <vector>

#include "core/gl/mesh_buffer.h"
#include "core/gl/shader_program.h"
#include "core/methods/fabric_method.h"

namespace loom {

inline constexpr int kMaxShadowMaps = 4;  // as in lights.glsl

struct SceneBounds {
  glm::vec3 centre{0.0f};
  float radius = 1.0f;
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

  // Renders one map per direction (unit, towards the light; at most
  // kMaxShadowMaps) covering `bounds`; matrix(i) maps world space to map i's [0,1]³.
  // Cloth binds its fabric's textures to units from `fabric_unit` on.
  void Render(const std::vector<glm::vec3>& directions, const SceneBounds& bounds,
              const std::vector<const gl::MeshBuffer*>& opaque, const std::vector<ClothCaster>& cloth,
              int fabric_unit);

  GLuint texture() const { return texture_; }
  const glm::mat4& matrix(int layer) const { return matrices_[static_cast<size_t>(layer)]; }
  const std::vector<glm::mat4>& matrices() const { return matrices_; }  // of the last Render's maps
  int size() const { return size_; }
  // World-space offset along the normal that keeps a lit surface from shadowing itself.
  float bias() const { return bias_; }

 private:
  int size_;
  GLuint texture_ = 0;
  GLuint framebuffer_ = 0;
  gl::ShaderProgram opaque_program_;
  gl::ShaderProgram cloth_program_;
  std::vector<glm::mat4> matrices_;
  float bias_ = 0.0f;
};

}  // namespace loom
