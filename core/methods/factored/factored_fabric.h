#pragma once
// The factored method's data: per level, texel and colour channel, the tabulated
// radiance L(v, l) (tabulated_fabric.h: the pooled samples, holes filled from the
// parent) approximated by K separable terms,
//   L(v, l) ≈ Σ_k A_k(v) · B_k(l),
// a view table A_k and a light table B_k per term: the truncated singular value
// decomposition of the texel's V×L matrix, the best rank-K approximation in the
// least-squares sense (Eckart–Young), each term's singular value split evenly
// between its two tables. A light that moves across a yarn moves its shadow through
// the light tables; a view through the view tables.
//
// The renderer interpolates A_k bilinearly between stored views and B_k between
// stored lights. Bilinear interpolation is linear in each table, so the sum of the
// interpolated products is the bilinear interpolation of the rank-K table: the
// method renders what tabulated would render of its rank-K approximation. The sum is
// clamped at 0 (a truncated SVD may dip below it). Ambient: Σ_k A_k(v)·b̄_k with
// b̄_k = 2π/L Σ_l B_k(l), stored per view in the view atlas beside alpha.

#include <cstdint>
#include <functional>
#include <glm/glm.hpp>
#include <vector>

#include "core/methods/tabulated/tabulated_fabric.h"

namespace loom {

struct FactoredLevel {
  uint32_t resolution = 0;
  // Texel (x, y) is index y·resolution + x.
  std::vector<glm::vec3> view_terms;   // A: [(texel·K + k)·V + view], RGB
  std::vector<glm::vec3> light_terms;  // B: [(texel·K + k)·L + light], RGB
  std::vector<float> alpha;            // [texel·V + view]
  std::vector<glm::vec3> ambient;      // [texel·V + view]
  // RMSE of the rank-K table against the tabulated one over every (texel, view,
  // light, channel), over their mean: what the factorisation loses.
  double relative_rmse = 0.0;

  size_t texel_count() const { return size_t{resolution} * resolution; }
};

struct FactoredFabric {
  uint32_t rank = 0;  // K
  std::vector<glm::vec3> view_directions;
  std::vector<glm::vec3> light_directions;
  std::vector<FactoredLevel> levels;  // levels[0] is the finest
  float sampling_height = 0.0f;
  double seconds = 0.0;  // wall time of FactorFabric

  size_t view_count() const { return view_directions.size(); }
  size_t light_count() const { return light_directions.size(); }
};

// Every level of `table` factored with `rank` terms (capped at min(V, L)), the
// texels spread over `threads` threads (0: every core); deterministic whatever
// the thread count. progress(fraction) after each level.
FactoredFabric FactorFabric(const TabulatedFabric& table, uint32_t rank, unsigned threads = 0,
                            const std::function<void(double)>& progress = {});

// The renderer's radiance (rgb, per unit irradiance of a light from `light`) and
// alpha (a) of texel `texel` of `level` seen from `view` (core/shaders/factored.glsl).
glm::vec4 EvaluateFactored(const FactoredFabric& fabric, uint32_t level, size_t texel, glm::vec3 view,
                           glm::vec3 light);

}  // namespace loom
