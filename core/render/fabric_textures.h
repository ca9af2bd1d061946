#pragma once
// A fitted fabric (the svbrdf method) in GPU memory, in the layout
// core/shaders/svbrdf.glsl reads:
//
// params: a 2-D array texture, RGBA float, whose mip level ℓ is fitted level ℓ
//   (resolution >> ℓ texels a side; fitted, not filtered), one texel attribute
//   per layer:
//     0: ρ.rgb              1: normal.xyz          2: tangent.xyz
//     3 + 3i: C_x,i.rgb, N_i.r   4 + 3i: C_y,i.rgb, N_i.g   5 + 3i: C_z,i.rgb, N_i.b
//   for i < kMaxLafortuneLobes (unused lobes zero: C = 0 turns a lobe off).
// lut: the view atlas (core/shaders/fabric_surface.glsl), RGBA float (T(v).rgb,
//   alpha(v)), mip level ℓ an atlas of
//   (resolution_ℓ · k)² texels: texel (x, y)'s table is the k×k block at
//   (x·k, y·k), view (col, row) of the hemisphere grid (core/acquire/
//   hemisphere_directions.h) at (x·k + col, y·k + row). Linear filtering inside a
//   block interpolates T between stored views.
//
// FabricTextureData is the same layout in CPU memory: what a fabric asset loads
// into and what tests build by hand.

#include <GL/glcorearb.h>

#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "core/fit/fabric_fit.h"
#include "core/gl/shader_program.h"
#include "core/methods/fabric_method.h"

namespace loom {

inline constexpr uint32_t kFabricParamLayers = 3 + 3 * 3;

struct FabricTextureData {
  uint32_t resolution = 0;  // level-0 texels per tile side (a power of two)
  uint32_t lobes = 0;       // lobes evaluated (≤ 3)
  uint32_t view_side = 0;   // k
  std::vector<float> view_heights;  // FittedFabric::view_heights (k²)
  // Per level ℓ: kFabricParamLayers layers of r_ℓ² texels, layer-major, rows
  // bottom-up in tile y (texel (x, y) at [layer][y·r_ℓ + x]).
  std::vector<std::vector<glm::vec4>> params;
  // Per level ℓ: the (r_ℓ·k)² atlas, row-major, rows in tile y order.
  std::vector<std::vector<glm::vec4>> lut;

  uint32_t levels() const { return static_cast<uint32_t>(params.size()); }
  uint32_t LevelResolution(uint32_t level) const { return resolution >> level; }
  glm::vec4& Param(uint32_t level, uint32_t layer, uint32_t x, uint32_t y) {
    const uint32_t r = LevelResolution(level);
    return params[level][(size_t{layer} * r + y) * r + x];
  }
  glm::vec4& Lut(uint32_t level, uint32_t x, uint32_t y, uint32_t view) {
    const uint32_t row = LevelResolution(level) * view_side;
    return lut[level][size_t{y * view_side + view / view_side} * row + x * view_side + view % view_side];
  }
  // Zeroed storage for `levels` levels (view heights 0: the macro surface).
  void Allocate(uint32_t resolution, uint32_t lobes, uint32_t view_side, uint32_t levels);

  // The layout above, filled from a fit.
  static FabricTextureData FromFit(const FittedFabric& fit);
};

class FabricTextures final : public GpuFabric {
 public:
  // `half` stores the lookup table in 16-bit floats (half its memory); the
  // parameters stay 32-bit, as in the asset: the lobes' C^N amplifies rounding.
  FabricTextures(const FabricTextureData& data, bool half);
  ~FabricTextures() override;
  FabricTextures(const FabricTextures&) = delete;
  FabricTextures& operator=(const FabricTextures&) = delete;

  const FabricMethod& method() const override;
  // The LUT (the view atlas) at `first_unit`, the view heights next, the parameters
  // at `first_unit + FabricSurface::kUnits`.
  void Bind(const gl::ShaderProgram& program, int first_unit, glm::vec2 repeat) const override;

 private:
  GLuint params_ = 0;
  GLuint lut_ = 0;
  uint32_t resolution_, lobes_, view_side_, levels_;
  FabricSurface surface_;
};

}  // namespace loom
