#include "core/methods/neural/neural_fabric.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "core/methods/direction_grid.h"
#include "core/spec/limits.h"
#include "core/util/error.h"
#include "core/util/parallel_for.h"
#include "core/util/stopwatch.h"

namespace loom {
namespace {

using Matrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic>;
using RowMajor = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using Weights = Eigen::Map<const RowMajor>;
using WeightGradients = Eigen::Map<RowMajor>;
using Bias = Eigen::Map<const Eigen::VectorXf>;
using BiasGradient = Eigen::Map<Eigen::VectorXf>;

// Where each layer's weights and biases start in NeuralDecoder::parameters.
struct Layout {
  Eigen::Index n, h;  // inputs, hidden
  size_t w1, b1, w2, b2, w3, b3;
  explicit Layout(const NeuralDecoder& decoder)
      : n(decoder.inputs()), h(decoder.hidden), w1(0), b1(w1 + size_t(h * n)), w2(b1 + size_t(h)), b2(w2 + size_t(h * h)),
        w3(b2 + size_t(h)), b3(w3 + size_t(3 * h)) {}
};

// The decoder over the columns of `x` (inputs × m): hidden activations and output.
struct Activations {
  Matrix h1, h2, y;
};

void Forward(const float* p, const Layout& o, const Matrix& x, Activations& a) {
  a.h1.noalias() = Weights(p + o.w1, o.h, o.n) * x;
  a.h1 = (a.h1.colwise() + Bias(p + o.b1, o.h)).cwiseMax(0.0f);
  a.h2.noalias() = Weights(p + o.w2, o.h, o.h) * a.h1;
  a.h2 = (a.h2.colwise() + Bias(p + o.b2, o.h)).cwiseMax(0.0f);
  a.y.noalias() = Weights(p + o.w3, 3, o.h) * a.h2;
  a.y.colwise() += Bias(p + o.b3, 3);
}

// Uniform draws from a generator whose sequence the standard fixes (mt19937_64), so
// training repeats on every standard library.
class Draw {
 public:
  explicit Draw(uint64_t seed) : engine_(seed) {}
  // In [0, n).
  uint32_t Below(uint64_t n) { return static_cast<uint32_t>(((engine_() >> 32) * n) >> 32); }
  // In [-1, 1).
  float Symmetric() { return static_cast<float>(engine_() >> 40) * 0x1.0p-23f - 1.0f; }

 private:
  std::mt19937_64 engine_;
};

struct Sample {
  uint32_t level, texel, view, light;
};

// Adam (Kingma and Ba 2015) over every parameter at once, decoder and latents.
class Adam {
 public:
  explicit Adam(size_t count) : m_(count, 0.0f), v_(count, 0.0f) {}
  void Step(std::vector<float>& parameters, const std::vector<float>& gradient, float rate) {
    ++t_;
    const float c1 = 1.0f - std::pow(kBeta1, static_cast<float>(t_));
    const float c2 = 1.0f - std::pow(kBeta2, static_cast<float>(t_));
    // A loop the compiler vectorises, square root included (this file is compiled
    // with -fno-math-errno; Eigen's own square root is an approximation under its
    // EIGEN_FAST_MATH default).
    for (size_t i = 0; i < parameters.size(); ++i) {
      m_[i] = kBeta1 * m_[i] + (1.0f - kBeta1) * gradient[i];
      v_[i] = kBeta2 * v_[i] + (1.0f - kBeta2) * gradient[i] * gradient[i];
      parameters[i] -= rate * (m_[i] / c1) / (std::sqrt(v_[i] / c2) + 1e-8f);
    }
  }

 private:
  static constexpr float kBeta1 = 0.9f, kBeta2 = 0.999f;
  std::vector<float> m_, v_;
  uint64_t t_ = 0;
};

constexpr uint32_t kChunks = 8;  // a step's samples in fixed chunks: the same sums on any thread count
constexpr float kRate = 5e-3f;   // Adam's step, decayed by a cosine to a twentieth

// The direction encoding of every stored (view, light) pair, [(view·L + light)·E + i].
std::vector<float> EncodePairs(const TabulatedFabric& table, uint32_t frequencies) {
  const size_t size = 4 * (1 + 2 * size_t{frequencies});
  std::vector<float> encodings(table.view_count() * table.light_count() * size);
  for (size_t view = 0; view < table.view_count(); ++view) {
    for (size_t light = 0; light < table.light_count(); ++light) {
      DirectionEncoding(glm::vec2(table.view_directions[view]), glm::vec2(table.light_directions[light]),
                        frequencies, &encodings[(view * table.light_count() + light) * size]);
    }
  }
  return encodings;
}

// The factored base's shape at a stored (view, light) of a texel of `level`; 0 without
// a base.
float StoredShape(const FactoredFabric& base, size_t level, size_t texel, size_t view, size_t light) {
  if (base.rank == 0) return 0.0f;
  const FactoredLevel& terms = base.levels[level];
  const size_t views = base.view_count(), lights = base.light_count();
  float sum = 0.0f;
  for (uint32_t k = 0; k < base.rank; ++k) {
    const size_t term = texel * base.rank + k;
    sum += terms.view_terms[term * views + view] * terms.light_terms[term * lights + light];
  }
  return sum;
}

// Decodes every (texel, view, light) of level `j` of `table` with the trained
// parameters, as the renderer does (the gain times the base's shape plus f, clamped
// at 0): the error against the table.
void Summarise(const NeuralDecoder& decoder, const FactoredFabric& base, size_t j, const TabulatedLevel& table,
               const std::vector<float>& encodings, size_t v_count, size_t l_count, unsigned threads,
               NeuralLevel& level) {
  const Layout o(decoder);
  const size_t texels = level.texel_count(), size = decoder.inputs() - decoder.channels;
  level.alpha = table.alpha;
  level.ambient = table.ambient;
  std::vector<double> residual(texels, 0.0), total(texels, 0.0);
  ParallelFor(texels, threads, [&](size_t texel, unsigned) {
    Matrix x(o.n, static_cast<Eigen::Index>(l_count));
    Activations a;
    for (Eigen::Index c = 0; c < Eigen::Index(decoder.channels); ++c) {
      x.row(c).setConstant(level.latents[texel * decoder.channels + size_t(c)]);
    }
    for (size_t view = 0; view < v_count; ++view) {
      for (size_t l = 0; l < l_count; ++l) {
        std::copy_n(&encodings[(view * l_count + l) * size], size, &x(decoder.channels, Eigen::Index(l)));
      }
      Forward(decoder.parameters.data(), o, x, a);
      const glm::vec3 gain = table.ambient[texel * v_count + view] / std::numbers::pi_v<float>;
      for (size_t l = 0; l < l_count; ++l) {
        const glm::vec3 target = table.radiance[(texel * v_count + view) * l_count + l];
        const float base_shape = StoredShape(base, j, texel, view, l);
        for (int c = 0; c < 3; ++c) {
          const float shape = a.y(c, Eigen::Index(l)) + base_shape;
          const float value = gain[c] * std::max(shape, 0.0f);
          residual[texel] += double(value - target[c]) * double(value - target[c]);
          total[texel] += target[c];
        }
      }
    }
  });
  level.relative_rmse = RelativeRmse(residual, total, texels * v_count * l_count * 3);
}

}  // namespace

void DirectionEncoding(glm::vec2 view, glm::vec2 light, uint32_t frequencies, float* out) {
  const float raw[4] = {view.x, view.y, light.x, light.y};
  std::copy_n(raw, 4, out);
  for (uint32_t k = 0; k < frequencies; ++k) {
    const float scale = std::numbers::pi_v<float> * static_cast<float>(1u << k);
    for (int i = 0; i < 4; ++i) {
      out[4 + 8 * k + i] = std::sin(scale * raw[i]);
      out[8 + 8 * k + i] = std::cos(scale * raw[i]);
    }
  }
}

glm::vec3 NeuralDecoder::Decode(const float* latent, glm::vec2 view, glm::vec2 light) const {
  const Layout o(*this);
  const float* p = parameters.data();
  float h1[kMaxNeuralHidden], h2[kMaxNeuralHidden];
  float encoding[4 * (1 + 2 * kMaxNeuralFrequencies)];
  DirectionEncoding(view, light, frequencies, encoding);
  const uint32_t directions = inputs() - channels;
  for (Eigen::Index j = 0; j < o.h; ++j) {
    const float* row = p + o.w1 + size_t(j * o.n);
    float sum = p[o.b1 + size_t(j)];
    for (uint32_t i = 0; i < channels; ++i) sum += row[i] * latent[i];
    for (uint32_t i = 0; i < directions; ++i) sum += row[channels + i] * encoding[i];
    h1[j] = std::max(sum, 0.0f);
  }
  for (Eigen::Index j = 0; j < o.h; ++j) {
    const float* row = p + o.w2 + size_t(j * o.h);
    float sum = p[o.b2 + size_t(j)];
    for (Eigen::Index i = 0; i < o.h; ++i) sum += row[i] * h1[i];
    h2[j] = std::max(sum, 0.0f);
  }
  glm::vec3 y;
  for (int c = 0; c < 3; ++c) {
    const float* row = p + o.w3 + size_t(c * o.h);
    float sum = p[o.b3 + size_t(c)];
    for (Eigen::Index i = 0; i < o.h; ++i) sum += row[i] * h2[i];
    y[c] = sum;
  }
  return y;
}

NeuralFabric TrainNeural(const TabulatedFabric& table, const NeuralTraining& training, unsigned threads,
                         const std::function<void(double)>& progress) {
  if (training.channels == 0 || training.channels % 4 != 0 || training.channels > kMaxNeuralChannels ||
      training.hidden == 0 || training.hidden % 4 != 0 || training.hidden > kMaxNeuralHidden ||
      training.frequencies > kMaxNeuralFrequencies) {
    throw Error(ErrorCode::kInvalidArgument, "neural training: channels and hidden must be positive multiples of 4, "
                                             "and they and frequencies within the limits of core/spec/limits.h");
  }
  const Stopwatch stopwatch;
  const uint32_t channels = training.channels;
  const size_t views = table.view_count(), lights = table.light_count();
  NeuralFabric fabric;
  fabric.decoder.channels = channels;
  fabric.decoder.hidden = training.hidden;
  fabric.decoder.frequencies = training.frequencies;
  const Layout o(fabric.decoder);
  fabric.steps = training.steps;
  fabric.view_directions = table.view_directions;
  fabric.light_directions = table.light_directions;
  fabric.view_heights = table.view_heights;
  if (training.base_rank > 0) fabric.base = FactorFabric(table, training.base_rank, threads);

  // One parameter vector: the decoder, then each level's latents.
  const size_t decoder_count = NeuralDecoder::ParameterCount(channels, training.hidden, training.frequencies);
  std::vector<size_t> latent_start;
  size_t count = decoder_count;
  for (const TabulatedLevel& level : table.levels) {
    latent_start.push_back(count);
    count += level.texel_count() * channels;
  }
  std::vector<float> theta(count, 0.0f);
  const std::vector<float> encodings = EncodePairs(table, training.frequencies);
  const size_t encoding_size = fabric.decoder.inputs() - channels;
  Draw draw(training.seed);
  // He-uniform weights for ReLU layers, zero biases, the output bias at ½ (f of a
  // Lambertian texel is cos θ_l) or, over a base, 0 (f is what the base leaves);
  // latents uniform in [-½, ½].
  const auto fill = [&](size_t start, size_t n, Eigen::Index fan_in) {
    const float bound = std::sqrt(6.0f / static_cast<float>(fan_in));
    for (size_t i = 0; i < n; ++i) theta[start + i] = bound * draw.Symmetric();
  };
  fill(o.w1, size_t(o.h * o.n), o.n);
  fill(o.w2, size_t(o.h * o.h), o.h);
  fill(o.w3, size_t(3 * o.h), o.h);
  for (int c = 0; c < 3; ++c) theta[o.b3 + size_t(c)] = fabric.base.rank > 0 ? 0.0f : 0.5f;
  for (size_t i = decoder_count; i < count; ++i) theta[i] = 0.5f * draw.Symmetric();

  Adam adam(count);
  std::vector<float> gradient(count);
  std::vector<Sample> batch(kNeuralBatch);
  constexpr uint32_t chunk = kNeuralBatch / kChunks;
  // Each chunk's inputs, activations and gradients, kept from step to step.
  struct Chunk {
    Matrix x, target, gain, d1, d2, d3;
    Activations a;
    std::vector<float> decoder;  // the decoder's gradient
    Matrix latent;               // C × chunk: each sample's latent gradient
  };
  std::vector<Chunk> chunks(kChunks);
  for (Chunk& c : chunks) {
    c.x.resize(o.n, chunk);
    c.target.resize(3, chunk);
    c.gain.resize(3, chunk);
    c.decoder.resize(decoder_count);
  }
  const uint32_t report = std::max<uint32_t>(training.steps / 100, 1);
  // Every level drawn equally often: the coarse levels, which distant cloth shows,
  // get as much of the shared decoder's attention as the finest (docs/methods/neural.md).
  const auto draw_batch = [&](size_t) {
    for (Sample& s : batch) {
      s.level = draw.Below(table.levels.size());
      s.texel = draw.Below(table.levels[s.level].texel_count());
      s.view = draw.Below(views);
      s.light = draw.Below(lights);
    }
  };
  const auto chunk_gradient = [&](size_t, size_t k, unsigned) {
    Chunk& scratch = chunks[k];
    Matrix &x = scratch.x, &target = scratch.target, &gain = scratch.gain;
    for (uint32_t s = 0; s < chunk; ++s) {
      const Sample& sample = batch[k * chunk + s];
      const float* z = &theta[latent_start[sample.level] + size_t{sample.texel} * channels];
      for (uint32_t c = 0; c < channels; ++c) x(c, s) = z[c];
      std::copy_n(&encodings[(size_t{sample.view} * lights + sample.light) * encoding_size], encoding_size,
                  &x(channels, s));
      const TabulatedLevel& level = table.levels[sample.level];
      const size_t pair = size_t{sample.texel} * views + sample.view;
      const glm::vec3 t = level.radiance[pair * lights + sample.light];
      const glm::vec3 a = level.ambient[pair] / std::numbers::pi_v<float>;
      // f is fitted to what the base's shape leaves: gain ⊙ (s + f) ≈ t.
      const glm::vec3 left = t - a * StoredShape(fabric.base, sample.level, sample.texel, sample.view, sample.light);
      target.col(s) << left.x, left.y, left.z;
      gain.col(s) << a.x, a.y, a.z;
    }
    Activations& a = scratch.a;
    Forward(theta.data(), o, x, a);
    // Loss: the mean squared error of gain ⊙ f over the batch's samples and channels.
    Matrix &d1 = scratch.d1, &d2 = scratch.d2, &d3 = scratch.d3;
    d3 = (gain.cwiseProduct(a.y) - target).cwiseProduct(gain) * (2.0f / (3.0f * kNeuralBatch));
    float* g = scratch.decoder.data();
    WeightGradients(g + o.w3, 3, o.h).noalias() = d3 * a.h2.transpose();
    BiasGradient(g + o.b3, 3) = d3.rowwise().sum();
    d2 = (Weights(theta.data() + o.w3, 3, o.h).transpose() * d3)
             .cwiseProduct((a.h2.array() > 0.0f).cast<float>().matrix());
    WeightGradients(g + o.w2, o.h, o.h).noalias() = d2 * a.h1.transpose();
    BiasGradient(g + o.b2, o.h) = d2.rowwise().sum();
    d1 = (Weights(theta.data() + o.w2, o.h, o.h).transpose() * d2)
             .cwiseProduct((a.h1.array() > 0.0f).cast<float>().matrix());
    WeightGradients(g + o.w1, o.h, o.n).noalias() = d1 * x.transpose();
    BiasGradient(g + o.b1, o.h) = d1.rowwise().sum();
    scratch.latent.noalias() = Weights(theta.data() + o.w1, o.h, o.n).leftCols(channels).transpose() * d1;
  };
  // The chunks' gradients summed in chunk order, whatever thread computed them.
  const auto descend = [&](size_t step) {
    std::fill(gradient.begin(), gradient.end(), 0.0f);
    for (uint32_t k = 0; k < kChunks; ++k) {
      for (size_t i = 0; i < decoder_count; ++i) gradient[i] += chunks[k].decoder[i];
      for (uint32_t s = 0; s < chunk; ++s) {
        const Sample& sample = batch[k * chunk + s];
        float* g = &gradient[latent_start[sample.level] + size_t{sample.texel} * channels];
        for (uint32_t c = 0; c < channels; ++c) g[c] += chunks[k].latent(c, s);
      }
    }
    const float progress_fraction = static_cast<float>(step) / static_cast<float>(training.steps);
    const float rate = kRate * (0.05f + 0.95f * 0.5f * (1.0f + std::cos(std::numbers::pi_v<float> * progress_fraction)));
    adam.Step(theta, gradient, rate);
    if (progress && (step + 1) % report == 0) progress(0.9 * double(step + 1) / training.steps);
  };
  ParallelRounds(training.steps, kChunks, threads, draw_batch, chunk_gradient, descend);

  fabric.decoder.parameters.assign(theta.begin(), theta.begin() + std::ptrdiff_t(decoder_count));
  for (size_t j = 0; j < table.levels.size(); ++j) {
    NeuralLevel& level = fabric.levels.emplace_back();
    level.resolution = table.levels[j].resolution;
    const auto start = theta.begin() + std::ptrdiff_t(latent_start[j]);
    level.latents.assign(start, start + std::ptrdiff_t(level.texel_count() * channels));
    Summarise(fabric.decoder, fabric.base, j, table.levels[j], encodings, views, lights, threads, level);
  }
  if (progress) progress(1.0);
  fabric.seconds = stopwatch.Seconds();
  return fabric;
}

glm::vec4 EvaluateNeural(const NeuralFabric& fabric, uint32_t level_index, size_t texel, glm::vec3 view,
                         glm::vec3 light) {
  const NeuralLevel& level = fabric.levels.at(level_index);
  const GridPoint v = LocateOnGrid(view, GridSide(fabric.view_count()));
  const GridPoint l = LocateOnGrid(light, GridSide(fabric.light_count()));
  glm::vec3 f = fabric.decoder.Decode(&level.latents.at(texel * fabric.decoder.channels), glm::vec2(view),
                                      glm::vec2(light));
  if (fabric.base.rank > 0) f += FactoredShape(fabric.base, level_index, texel, v, l);
  return GainTimesShape(level, texel, fabric.view_count(), v, LightWeight(light, l), f);
}

}  // namespace loom
