#pragma once
// What the stability suite measures where a method is pushed to the edge of its
// range (issue 7 "Stability where methods fail"), and how each figure is bounded
// and reported.
//
// Every figure is checked against its bound (a failing EXPECT names it), recorded
// as a test property, and — when LOOM_STABILITY_CSV names a file — appended to it
// as one CSV row `regime,method,metric,value,bound`; scripts/stability_csv.sh
// collects them into docs/results/stability.csv. A bound is "<=x", ">=x", or
// "none" for a figure the suite documents without bounding it (the case lies
// outside the method's range; docs/stability.md says why).

#include <string>

#include "core/fit/fabric_fit.h"
#include "core/image/image.h"
#include "core/metrics/image_metrics.h"
#include "tests/core/render/comparison_scene.h"

namespace loom::testing {

struct Bound {
  enum Kind { kAtMost, kAtLeast, kNone } kind = kNone;
  double limit = 0.0;
};
inline Bound AtMost(double limit) { return {Bound::kAtMost, limit}; }
inline Bound AtLeast(double limit) { return {Bound::kAtLeast, limit}; }
inline Bound Unbounded() { return {}; }

// Checks `value` against `bound` (EXPECT), records and reports it.
void Figure(const std::string& regime, const std::string& method, const std::string& metric, double value,
            Bound bound);

// Non-finite values (NaN or ±Inf) among a frame's pixels, every channel.
size_t NonFiniteCount(const Image& image);

// Non-finite values in everything a fitted fabric hands the renderer: every
// level's BRDF parameters, lookup table, alpha, frame and RMSE, and its figures.
size_t NonFiniteCount(const FittedFabric& fit);

// Texels of every level that lost lobes (fewer lobes or diffuse only), and the
// texels fitted in all (empty ones excluded).
struct FitFallbacks {
  uint64_t fallbacks = 0;
  uint64_t fitted = 0;
  double fraction() const { return fitted ? static_cast<double>(fallbacks) / fitted : 0.0; }
};
FitFallbacks CountFallbacks(const FittedFabric& fit);

// The figures of one svbrdf-vs-reference comparison under `regime`: no NaN/Inf in
// either frame (bounded at 0 always), PSNR and the mean-radiance ratio's distance
// from 1 against the given bounds, recorded as `method`'s (an svbrdf variant, e.g.
// "svbrdf_anisotropic"). Returns the comparison for further checks.
struct ComparisonBounds {
  Bound psnr_db = Unbounded();
  Bound mean_ratio_error = Unbounded();  // |mean(svbrdf) / mean(reference) − 1| over the red channel
};
ImageComparison CompareMethods(const std::string& regime, const Image& svbrdf, const Image& reference,
                               const ComparisonBounds& bounds, const std::string& method = "svbrdf");

// log10 of the largest lobe peak of any texel, level and channel, max_k |C_k|^N,
// over the peak of an energy-conserving cosine lobe of the same exponent,
// (N + 2)/2π: how far the fitted model can overshoot between sampled directions.
double LobePeakLog10Ratio(const FittedFabric& fit);

// The fit's figures under `regime`: no NaN/Inf in the asset (bounded at 0), no
// lobe peak beyond the fit's limit (LobePeakLog10Ratio ≤ 1), the fallback
// fraction against `fallback_fraction`.
void CheckFit(const std::string& regime, const FittedFabric& fit, Bound fallback_fraction);

// One regime end to end: the comparison scene made from `options`, its two
// methods compared (CompareMethods) and its fit checked (CheckFit).
ImageComparison CheckRegime(const std::string& regime, const ComparisonOptions& options,
                            const ComparisonBounds& bounds, Bound fallback_fraction);

}  // namespace loom::testing
