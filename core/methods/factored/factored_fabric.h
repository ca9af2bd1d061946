#pragma once
// The factored method's data: per level and texel, the tabulated radiance
// (tabulated_fabric.h) as the texel's ambient response A(v) (RGB, per stored view:
// 2π/L·Σ_l L(v, l), the table's own, as the neural method's gain) times a shape
// that K separable terms hold, L(v, l) ≈ A(v)/π ⊙ max(0, Σ_k a_k(v)·b_k(l)): one
// view table a_k and one light table b_k per term, shared by the three colour
// channels. The shape is the truncated SVD of the texel's V×L table of
// A(v)·L(v, l)/|A(v)|² (the colour's least-squares projection on A), rows weighted
// by |A(v)| so that it minimises the error in radiance. EvaluateFactored is the
// renderer's lookup in C++: A, a_k and b_k bilinear between stored directions.
// Derivation: docs/methods/factored.md.

#include <cstdint>
#include <functional>
#include <glm/glm.hpp>
#include <vector>

#include "core/methods/direction_grid.h"
#include "core/methods/tabulated/tabulated_fabric.h"

namespace loom {

struct FactoredLevel {
  uint32_t resolution = 0;
  // Texel (x, y) is index y·resolution + x.
  std::vector<float> view_terms;   // a: [(texel·K + k)·V + view]
  std::vector<float> light_terms;  // b: [(texel·K + k)·L + light]
  std::vector<float> alpha;        // [texel·V + view]
  std::vector<glm::vec3> ambient;  // [texel·V + view]: A
  // RMSE of the factored table (A/π ⊙ max(0, Σ a·b)) against the tabulated one over
  // every (texel, view, light, channel), over their mean: what the factorisation loses.
  double relative_rmse = 0.0;

  size_t texel_count() const { return size_t{resolution} * resolution; }
};

struct FactoredFabric {
  uint32_t rank = 0;  // K
  std::vector<glm::vec3> view_directions;
  std::vector<glm::vec3> light_directions;
  std::vector<FactoredLevel> levels;  // levels[0] is the finest
  std::vector<float> view_heights;  // RadianceSamples::view_heights
  double seconds = 0.0;  // wall time of FactorFabric

  size_t view_count() const { return view_directions.size(); }
  size_t light_count() const { return light_directions.size(); }
};

// Every level of `table` factored with `rank` terms (capped at min(V, L)), the
// texels spread over `threads` threads (0: every core); deterministic whatever
// the thread count. progress(fraction) after each level.
FactoredFabric FactorFabric(const TabulatedFabric& table, uint32_t rank, unsigned threads = 0,
                            const std::function<void(double)>& progress = {});

// The shape Σ_k a_k(v)·b_k(l) of texel `texel` of `level`, not clamped, a_k and b_k
// bilinear between the stored directions around the view and the light
// (core/shaders/factored_terms.glsl FactoredShape).
float FactoredShape(const FactoredFabric& fabric, uint32_t level, size_t texel, const GridPoint& view,
                    const GridPoint& light);

// The renderer's radiance (rgb, per unit irradiance of a light from `light`) and
// alpha (a) of texel `texel` of `level` seen from `view` (core/shaders/factored.glsl).
glm::vec4 EvaluateFactored(const FactoredFabric& fabric, uint32_t level, size_t texel, glm::vec3 view,
                           glm::vec3 light);

}  // namespace loom
