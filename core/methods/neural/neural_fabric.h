#pragma once
// The neural method's data (NeuMIP, Kuznetsov et al. 2021): per level and texel a
// latent vector z of C numbers, and one decoder shared by every texel and level, a
// multilayer perceptron f(z, e(v, l)) (two hidden layers of H ReLU units; v and l
// unit, tile frame; e the directions' encoding, DirectionEncoding). The radiance per
// unit irradiance of a light from l is A(v)/π ⊙ max(0, f): A the texel's ambient
// response per view, 2π/L·Σ_l L(v, l) from the tabulated samples (tabulated_fabric.h),
// stored like alpha per (texel, view) and interpolated between stored views, so f
// carries how the radiance varies with the light and A its colour and level per view.
// With a factored base of K terms (factored_fabric.h, K > 0) the radiance is
// A(v)/π ⊙ max(0, s + f), s = Σ_k a_k(v)·b_k(l) the factored method's shape of the
// same table, and f is fitted to what s leaves.
// Latents and decoder are trained together by Adam on the tabulated samples of every
// level, so each level's latents are fitted to that level's pooled samples (fitted mip
// levels). Deterministic for a seed and a step count, whatever the thread count.
// EvaluateNeural is the renderer's lookup in C++ (core/shaders/neural.glsl).
// Derivation: docs/methods/neural.md.

#include <cstdint>
#include <functional>
#include <glm/glm.hpp>
#include <vector>

#include "core/methods/factored/factored_fabric.h"
#include "core/methods/tabulated/tabulated_fabric.h"

namespace loom {

// The decoder's direction inputs, in groups of four: (v.x, v.y, l.x, l.y), then
// for k < F the sines of 2^k·π times those four and their cosines: 4·(1 + 2F)
// numbers. The view's are the first two of each group, the light's the last two.
void DirectionEncoding(glm::vec2 view, glm::vec2 light, uint32_t frequencies, float* out);

struct NeuralDecoder {
  uint32_t channels = 0;     // C, a multiple of 4
  uint32_t hidden = 0;       // H, a multiple of 4
  uint32_t frequencies = 0;  // F
  // Layer by layer, each weight matrix row-major (a row per output):
  // W1 [H × inputs] over (z, e), b1 [H], W2 [H × H], b2 [H], W3 [3 × H], b3 [3]:
  // the order of the shader's uniform block.
  std::vector<float> parameters;

  static uint32_t Inputs(uint32_t channels, uint32_t frequencies) { return channels + 4 * (1 + 2 * frequencies); }
  uint32_t inputs() const { return Inputs(channels, frequencies); }
  static size_t ParameterCount(uint32_t channels, uint32_t hidden, uint32_t frequencies) {
    return size_t{hidden} * Inputs(channels, frequencies) + hidden + size_t{hidden} * hidden + hidden +
           3 * size_t{hidden} + 3;
  }
  // f(z, e(v, l)), not clamped; `latent` holds C numbers.
  glm::vec3 Decode(const float* latent, glm::vec2 view, glm::vec2 light) const;
};

struct NeuralLevel {
  uint32_t resolution = 0;
  // Texel (x, y) is index y·resolution + x.
  std::vector<float> latents;      // [texel·C + c]
  std::vector<float> alpha;        // [texel·V + view]
  std::vector<glm::vec3> ambient;  // [texel·V + view]: A, the table's 2π/L · Σ_l L
  // RMSE of the decoded table (A/π ⊙ max(0, f)) against the tabulated one over every
  // (texel, view, light, channel), over their mean.
  double relative_rmse = 0.0;

  size_t texel_count() const { return size_t{resolution} * resolution; }
};

struct NeuralFabric {
  NeuralDecoder decoder;
  uint32_t steps = 0;  // training steps taken
  std::vector<glm::vec3> view_directions;
  std::vector<glm::vec3> light_directions;
  std::vector<NeuralLevel> levels;  // levels[0] is the finest
  std::vector<float> view_heights;  // RadianceSamples::view_heights
  // The factored base; rank 0: none. Only its levels' terms are used (the gain and
  // coverage are the levels' own).
  FactoredFabric base;
  double seconds = 0.0;  // wall time of TrainNeural

  size_t view_count() const { return view_directions.size(); }
  size_t light_count() const { return light_directions.size(); }
};

struct NeuralTraining {
  uint32_t channels = 8;
  uint32_t hidden = 32;
  uint32_t frequencies = 0;
  uint32_t steps = 1000;
  uint64_t seed = 0;
  uint32_t base_rank = 0;  // K of the factored base, 0: none
};

// Samples in one training step.
inline constexpr uint32_t kNeuralBatch = 1024;

// Latents and decoder for every level of `table`, trained for `training.steps`
// minibatches on `threads` threads (0: every core). progress(fraction) now and then;
// throwing from it stops the training.
NeuralFabric TrainNeural(const TabulatedFabric& table, const NeuralTraining& training, unsigned threads = 0,
                         const std::function<void(double)>& progress = {});

// The renderer's radiance (rgb, per unit irradiance of a light from `light`) and
// alpha (a) of texel `texel` of `level` seen from `view` (core/shaders/neural.glsl).
glm::vec4 EvaluateNeural(const NeuralFabric& fabric, uint32_t level, size_t texel, glm::vec3 view, glm::vec3 light);

}  // namespace loom
