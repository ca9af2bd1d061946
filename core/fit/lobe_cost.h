#pragma once
// The Levenberg–Marquardt problem of one texel's lobe fit in one colour channel
// (Daubert 2001 §5): minimise Σ_s e_s² over the valid samples s, with
//
//   e_s = T(view_s) · l_z,s · (ρ + Σ_i [C_i · a_s]^{N_i}) − r_s
//
// and the lookup table T held fixed; the parameters are one block x of
// p = 1 + 4·lobes values. The samples are compressed into p + 1 residuals with the
// same cost, gradient and Gauss–Newton matrix, so Ceres takes the full problem's
// steps; lobe powers are cached between evaluations, which makes a LobeCost
// single-threaded: one per solve. Derivation: docs/methods/svbrdf.md.

#include <ceres/ceres.h>

#include <cstdint>
#include <vector>

#include "core/fit/lafortune_brdf.h"

namespace loom {

// A texel's samples reduced to what the model needs: per sample the lobe argument
// (l_k v_k in the local frame), the cosine l_z clamped at 0 (times √n for a sample
// pooling n raw ones, texel_fit.h TexelSamples) and the view index. Shared by the
// three channels.
struct TexelGeometry {
  uint32_t view_count = 0;
  std::vector<LobeArgument> arguments;
  std::vector<double> cosines;
  std::vector<uint32_t> views;

  size_t size() const { return views.size(); }
};

// Parameter bounds that keep the model physical and finite: ρ ≥ 0 and bounded;
// |C| bounded (a lobe that needs more is a spike no direction grid resolves); N from
// a broad lobe (0.5) to a near-mirror one. A step whose lobe still overflows (large
// |C| with large N) is rejected by LobeCost::Evaluate.
inline constexpr double kMaxDiffuse = 1e3;
inline constexpr double kMaxLobeCoefficient = 50.0;
inline constexpr double kMinLobeExponent = 0.5;
inline constexpr double kMaxLobeExponent = 256.0;

class LobeCost final : public ceres::CostFunction {
 public:
  // Keeps references: geometry, radiance (one channel, one value per sample) and
  // lut (one value per view) must outlive the cost; lut may change between solves.
  LobeCost(const TexelGeometry& geometry, const std::vector<double>& radiance, const std::vector<double>& lut,
           uint32_t lobes);

  // Returns false (Ceres rejects the step) where a residual or derivative is not
  // finite, rather than hand Inf to the solver.
  //
  // e' and J' above, p + 1 values and (p + 1) × p row-major.
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

 private:
  // Fills lobe_values_ and lobe_logs_ for x unless they already hold x's.
  void UpdateLobeCache(const double* x) const;
  // e_s at x, from the cache.
  double Residual(const double* x, size_t s) const;
  // JᵀJ (column-major p × p) and Jᵀe at x from the cache; returns ‖e‖².
  template <uint32_t kLobes>
  double Accumulate(const double* x, double* normal, double* gradient) const;

  const TexelGeometry& geometry_;
  const std::vector<double>& radiance_;
  const std::vector<double>& lut_;
  uint32_t lobes_;
  mutable bool cache_valid_ = false;
  mutable std::vector<double> cached_x_;
  mutable std::vector<double> dots_;         // C_i · a_s of one lobe, scratch
  mutable std::vector<double> lobe_values_;  // [C_i · a_s]^{N_i} at [i·samples + s], 0 where off
  mutable std::vector<double> lobe_logs_;    // log(C_i · a_s) where on, else 0
};

// Adds x (1 + 4·lobes values, LafortuneChannel's packing) as the problem's one
// parameter block, with the bounds above.
void AddLobeParameterBounds(ceres::Problem& problem, double* x, uint32_t lobes);

// Levenberg–Marquardt, dense normal equations (the compressed problem is at most
// 14 × 13), one thread: fitting is parallel across texels, not inside one.
ceres::Solver::Options LobeSolverOptions(uint32_t max_iterations);

}  // namespace loom
