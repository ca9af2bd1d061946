#pragma once
// Fitting one texel's BRDF and lookup table to its radiance samples (Daubert 2001
// §5): Levenberg–Marquardt for the lobes with T fixed, then T(v) per view in closed
// form (eq. 4), alternated until the mean |ΔT| falls below a threshold.
//
// What is fitted: the radiance samples r as acquisition stores them (unit
// irradiance, so r = f_r · cos θ_l), by T(v) · f_1(l, v) with f_1 the Lafortune model
// of core/fit/lafortune_brdf.h, which carries the cosine as l_z. The error is the
// plain sum of squared residuals over the valid samples (alpha > 0; the caller adds
// only those), every channel alike.
//
// Separability. Channel c of T · f_1 depends only on channel c of T and of every
// parameter, so a texel is three independent scalar problems of 1 + 4·lobes
// parameters plus one T per view, each with its own alternation: FitTexelChannel
// is the unit of work (the fabric fit schedules channels as separate items), and
// FitTexel runs the three and combines them.
//
// Start (§5): per channel ρ = Σ r / Σ l_z (the mean ratio of radiance to cosine),
// moderate specular lobes with N = 10 whose peak is half of ρ, slightly anisotropic
// (lobe 1 C_x = 1.22·C_y, lobe 2 C_y = 1.22·C_x; C_x, C_y < 0 < C_z reflect about
// the normal), a third lobe retro-reflective (C_x = C_y = C_z > 0), and T = 1.
//
// Fallbacks. A lobe fit is kept if Ceres returns a usable solution with finite
// values and its error is no worse than the closed-form diffuse fit (with its own
// T): anything else failed or diverged, and the channel is refitted with one lobe
// fewer, down to diffuse only. Before that, a fit whose table has settled above
// the diffuse fit's error keeps alternating while that still lowers its error. Dropped lobes stay in the layout with C = 0 (off).
// A final guard replaces any non-finite value by the diffuse fit, so no NaN or Inf
// ever leaves this file.

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "core/fit/lafortune_brdf.h"
#include "core/fit/lobe_cost.h"
#include "loom/v1/precompute.pb.h"

namespace loom {

// Ordered by how much of the requested model a texel lost; a texel's status is
// its worst channel's (a black channel next to fitted ones is ok).
enum class TexelFitStatus : uint8_t {
  kBlack,        // every valid sample is zero: ρ = 0, lobes off, exactly
  kOk,           // fitted with every requested lobe
  kFewerLobes,   // a channel failed with all lobes and kept fewer
  kDiffuseOnly,  // a channel failed with any lobe and kept the closed-form diffuse fit
  kEmpty,        // no valid sample (a hole from every view): zero here, the fabric
                 // fit fills it from a parent or neighbour
};
const char* TexelFitStatusName(TexelFitStatus status);

struct TexelFitOptions {
  uint32_t lobes = 2;
  bool lookup_table = true;
  double lut_change_threshold = 0.1;
  uint32_t max_alternations = 8;
  uint32_t max_lm_iterations = 50;
};
// From settings with the defaults of core/spec/defaults.h applied.
TexelFitOptions MakeTexelFitOptions(const v1::PrecomputeSettings& settings);

// One texel's valid samples, directions already in its local frame.
//
// Pooled samples. A mip texel fits the samples of its 2×2 children in its own
// frame, so the children's samples of one view and light have the same directions
// and differ only in radiance. Each raw sample also stands for a share of the
// texel's rays: its coverage w_j, the fraction of its texel's rays that hit yarn
// (acquisition's alpha), since a texel's radiance is the mean over its rays that
// hit. For radiances r_j with weights w_j, W = Σ w_j and r̄ = Σ w_j r_j / W,
//
//   Σ_j w_j (m − r_j)² = W (m − r̄)² + Σ_j w_j (r_j − r̄)²   for every model value m,
//
// so they are stored as one sample of radiance r̄ and weight W, and the spread
// Σ w_j (r_j − r̄)² (which no model can explain) is added back to the fit's error:
// the fit, its error and its RMSE are those of the raw rays that hit, at the cost
// of one sample. The weight is carried as √W on both the cosine and the radiance
// (e = T·l_z·f − r is linear in both), so every sum of squares over the stored
// samples is the weighted one and the fitting code needs no weights.
//
// Why coverage: a child hit by one ray in four must not count as much as a fully
// covered one. Unweighted, a coarse texel's target depended on the resolution its
// children were acquired at, so the same coarse level fitted from fine texels with
// few rays and from coarse texels with many differed (docs/results/plan.md).
class TexelSamples {
 public:
  explicit TexelSamples(uint32_t view_count);

  void Reserve(size_t count);
  // Unit light and view directions in the local frame, the view's index in the
  // stored view directions, the RGB radiance. Only samples with alpha > 0.
  void Add(glm::vec3 light, glm::vec3 view, uint32_t view_index, glm::vec3 radiance);
  // Raw samples with these directions and view, one radiance and one coverage
  // (> 0, at most 1) each, at least one, stored as one pooled sample.
  void AddPooled(glm::vec3 light, glm::vec3 view, uint32_t view_index, std::span<const glm::vec3> radiances,
                 std::span<const float> coverages);

  const TexelGeometry& geometry() const { return geometry_; }
  uint32_t view_count() const { return geometry_.view_count; }
  // Stored samples (what a fit iterates over).
  size_t size() const { return geometry_.size(); }
  // Channel c of every stored sample's radiance, √n-weighted.
  std::vector<double> Channel(int c) const;

  // Over the raw samples: their count, their summed coverage, channel c's
  // coverage-weighted radiance sum, and the spread within pooled samples that the
  // fit's error must add.
  size_t raw_count() const { return raw_count_; }
  double raw_weight() const { return raw_weight_; }
  double RadianceSum(int c) const { return radiance_sum_[c]; }
  double PooledSpread(int c) const { return spread_[c]; }

 private:
  void Push(glm::vec3 light, glm::vec3 view, uint32_t view_index, glm::dvec3 radiance, double weight);

  TexelGeometry geometry_;
  std::vector<glm::dvec3> radiance_;
  size_t raw_count_ = 0;
  double raw_weight_ = 0.0;
  glm::dvec3 radiance_sum_{0.0};
  glm::dvec3 spread_{0.0};
};

struct ChannelFit {
  std::vector<double> parameters;  // LafortuneChannel packing, options.lobes lobes
  std::vector<double> lut;         // T per view; 1 where a view has no sample
  double squared_error = 0.0;      // Σ residual² over the samples
  uint32_t lm_iterations = 0;      // over every alternation and fallback
  uint32_t alternations = 0;       // lobe fits of the kept attempt
  std::vector<double> lut_changes;  // mean |ΔT| after each lobe fit of the kept attempt
  TexelFitStatus status = TexelFitStatus::kOk;
  size_t samples = 0;               // the channel's valid raw samples
  double weight = 0.0;              // Σ w over them (TexelSamples)
  double radiance_sum = 0.0;        // Σ w r over them
};

// A start other than the paper's for the fit with every requested lobe:
// parameters (LafortuneChannel packing, options.lobes lobes, inside the bounds of
// lobe_cost.h) and T per view. The fit runs from the paper's start and from each
// given start and keeps the result with the least error (fallbacks to fewer lobes
// use the paper's start). A mip texel's start is its parent's fit, the top level's
// AlternativeStarts (core/fit/fabric_fit.h).
struct ChannelStart {
  std::vector<double> parameters;
  std::vector<double> lut;
};

ChannelFit FitTexelChannel(const TexelSamples& samples, int channel, const TexelFitOptions& options,
                           std::span<const ChannelStart> starts = {});

// Starts that depend on the texel's samples only, for a texel with no parent (the
// top mip level), whose minimum the paper's start alone often misses: the paper's
// with its last lobe retro-reflective (C_x = C_y = C_z), and with every lobe broad
// (exponent 3, the same peak).
std::vector<ChannelStart> AlternativeStarts(const TexelSamples& samples, int channel, uint32_t lobes);

// The paper's start (above) for one channel's radiance (one value per sample), packed as
// LafortuneChannel's x.
std::vector<double> StartParameters(const TexelGeometry& geometry, const std::vector<double>& radiance,
                                    uint32_t lobes);

struct TexelFit {
  LafortuneBrdf brdf;
  std::vector<glm::vec3> lut;  // T per view
  size_t samples = 0;          // valid samples (each RGB)
  double weight = 0.0;         // their summed coverage (TexelSamples)
  double rmse = 0.0;           // over every valid sample and channel, coverage-weighted
  double mean_radiance = 0.0;  // likewise; rmse / mean_radiance is the relative error
  uint32_t lm_iterations = 0;  // sum over the channels
  uint32_t alternations = 0;   // the most of any channel
  TexelFitStatus status = TexelFitStatus::kOk;
  std::array<std::vector<double>, 3> lut_changes;
};

// The three channel fits of one texel as one result.
TexelFit CombineChannelFits(const std::array<ChannelFit, 3>& channels, uint32_t lobes);

TexelFit FitTexel(const TexelSamples& samples, const TexelFitOptions& options);

}  // namespace loom
