#pragma once
// The tabulated method's data: a fabric's acquired radiance samples themselves, per
// mip level, texel, view and light — no fit (the ceiling of fitted methods). A texel
// of level k + 1 pools the level-0 texels it covers per (view, light), weighted by
// coverage; a (texel, view) with alpha 0 takes its parent's radiance. Per (texel,
// view) it also holds the ambient response, 2π/L · Σ_l L(v, l). EvaluateTabulated is
// the renderer's lookup in C++ (core/shaders/tabulated.glsl). Derivation:
// docs/methods/tabulated.md.

#include <algorithm>
#include <cstdint>
#include <glm/glm.hpp>
#include <numbers>
#include <vector>

#include "core/acquire/radiance_samples.h"
#include "core/methods/direction_grid.h"

namespace loom {

struct TabulatedLevel {
  uint32_t resolution = 0;
  // Texel (x, y) is index y·resolution + x; texel-major like RadianceSamples.
  std::vector<glm::vec3> radiance;  // [(texel·V + view)·L + light], per unit irradiance
  std::vector<float> alpha;         // [texel·V + view]
  std::vector<glm::vec3> ambient;   // [texel·V + view]

  size_t texel_count() const { return size_t{resolution} * resolution; }
};

struct TabulatedFabric {
  std::vector<glm::vec3> view_directions;   // HemisphereGridDirections order
  std::vector<glm::vec3> light_directions;  // HemisphereGridDirections order
  std::vector<TabulatedLevel> levels;       // levels[0] is the finest
  std::vector<float> view_heights;          // RadianceSamples::view_heights
  double seconds = 0.0;                     // wall time of TabulateFabric

  size_t view_count() const { return view_directions.size(); }
  size_t light_count() const { return light_directions.size(); }
};

// Every level down to 1×1 with `mip_levels` (the resolution must then be a power of
// two: Error(kInvalidArgument) otherwise), level 0 alone without.
TabulatedFabric TabulateFabric(const RadianceSamples& samples, bool mip_levels);

// How far a method's approximation of a tabulated level is from it: √(mean squared
// residual) / mean value over `count` values, from per-texel sums of the squared
// residuals and of the values (summed over texels in order: the same on any thread
// count); 0 for a level of zeros.
double RelativeRmse(const std::vector<double>& squared_residuals, const std::vector<double>& values, size_t count);

// What the methods that scale a shape by the ambient response (factored, neural)
// render from a texel of `level` (a level with per-(texel, view) `ambient` and `alpha`,
// `views` stored views) at `view` on the view grid: light_weight · A/π ⊙ max(0, shape),
// A and alpha bilinear between the stored views, alpha towards 1 past the outermost
// ring (fabric_surface.glsl FetchFabricView).
template <typename Level>
glm::vec4 GainTimesShape(const Level& level, size_t texel, size_t views, const GridPoint& view, float light_weight,
                         glm::vec3 shape) {
  const uint32_t side = GridSide(views);
  const glm::vec3 gain =
      Bilinear<glm::vec3>(view, side, [&](size_t stored) { return level.ambient[texel * views + stored]; }) /
      std::numbers::pi_v<float>;
  const float alpha = Bilinear<float>(view, side, [&](size_t stored) { return level.alpha[texel * views + stored]; });
  return {light_weight * gain * glm::max(shape, glm::vec3(0.0f)), glm::mix(alpha, 1.0f, view.beyond_ring)};
}

// The renderer's radiance (rgb, per unit irradiance of a light from `light`) and
// alpha (a) of texel `texel` of `level` seen from `view`, both unit, tile frame.
glm::vec4 EvaluateTabulated(const TabulatedFabric& fabric, uint32_t level, size_t texel, glm::vec3 view,
                            glm::vec3 light);

}  // namespace loom
