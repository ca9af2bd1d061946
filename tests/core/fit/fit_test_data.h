#pragma once
// Synthetic radiance for fitting tests: a known Lafortune BRDF and lookup table
// rendered on the hemisphere direction grids, as acquisition would store it.

#include <cstdint>
#include <functional>
#include <glm/glm.hpp>
#include <utility>
#include <vector>

#include "core/fit/lafortune_brdf.h"
#include "core/fit/texel_fit.h"

namespace loom::testing {

// T · f_1 for one (light, view) pair in the local frame.
glm::vec3 RenderModel(const LafortuneBrdf& brdf, const std::vector<glm::vec3>& lut, uint32_t view_index,
                      glm::vec3 light, glm::vec3 view);

struct SyntheticTexel {
  explicit SyntheticTexel(LafortuneBrdf brdf, std::vector<glm::vec3> lut = {}, double noise = 0.0, uint32_t seed = 1)
      : brdf(brdf), lut(std::move(lut)), noise(noise), seed(seed) {}

  LafortuneBrdf brdf;
  std::vector<glm::vec3> lut;  // T per view; empty means 1
  // Multiplicative Gaussian noise (standard deviation), deterministic from `seed`.
  double noise = 0.0;
  uint32_t seed = 1;
  // Which views the texel is visible from (alpha > 0); empty means all.
  std::function<bool(uint32_t view, glm::vec3 direction)> visible;
};

// Samples of `texel` on k×k view × k×k light grids (view_count = light_count = k²),
// directions in the local frame (the normal is +z).
TexelSamples MakeTexelSamples(const SyntheticTexel& texel, uint32_t view_count, uint32_t light_count);

// RMSE between the fit's model and the noise-free truth over the same grids and
// visible views, and the truth's mean.
struct RenderError {
  double rmse = 0.0;
  double mean = 0.0;
};
RenderError CompareRenders(const SyntheticTexel& truth, const TexelFit& fit, uint32_t view_count,
                           uint32_t light_count);

}  // namespace loom::testing
