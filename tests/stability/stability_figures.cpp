#include "tests/stability/stability_figures.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "tests/core/render/comparison_scene.h"

namespace loom::testing {
namespace {

std::string BoundText(Bound bound) {
  std::ostringstream text;
  text.precision(6);
  if (bound.kind == Bound::kAtMost) text << "<=" << bound.limit;
  if (bound.kind == Bound::kAtLeast) text << ">=" << bound.limit;
  if (bound.kind == Bound::kNone) text << "none";
  return text.str();
}

// One row appended per figure; ctest may run several test processes at once, so
// each row is one write to a file opened for appending.
void AppendCsvRow(const std::string& row) {
  const char* path = std::getenv("LOOM_STABILITY_CSV");
  if (path == nullptr || *path == '\0') return;
  std::FILE* file = std::fopen(path, "a");
  ASSERT_NE(file, nullptr) << "LOOM_STABILITY_CSV=" << path << " cannot be opened";
  std::fputs(row.c_str(), file);
  std::fclose(file);
}

size_t NonFinite(float v) { return std::isfinite(v) ? 0 : 1; }
size_t NonFinite(glm::vec3 v) { return NonFinite(v.x) + NonFinite(v.y) + NonFinite(v.z); }

}  // namespace

void Figure(const std::string& regime, const std::string& method, const std::string& metric, double value,
            Bound bound) {
  const std::string name = regime + "/" + method + "/" + metric;
  std::ostringstream row;
  row.precision(6);
  row << regime << ',' << method << ',' << metric << ',' << value << ',' << BoundText(bound) << '\n';
  ::testing::Test::RecordProperty(name, row.str());
  AppendCsvRow(row.str());
  EXPECT_TRUE(std::isfinite(value)) << name << " = " << value;
  if (bound.kind == Bound::kAtMost) {
    EXPECT_LE(value, bound.limit) << name;
  } else if (bound.kind == Bound::kAtLeast) {
    EXPECT_GE(value, bound.limit) << name;
  }
}

size_t NonFiniteCount(const Image& image) {
  size_t count = 0;
  for (float v : image.pixels) count += NonFinite(v);
  return count;
}

size_t NonFiniteCount(const FittedFabric& fit) {
  size_t count = 0;
  for (const FittedLevel& level : fit.levels) {
    for (const LafortuneBrdf& brdf : level.brdfs) count += brdf.AllFinite() ? 0 : 1;
    for (glm::vec3 t : level.lut) count += NonFinite(t);
    for (float a : level.alpha) count += NonFinite(a);
    for (glm::vec3 n : level.normals) count += NonFinite(n);
    for (glm::vec3 t : level.tangents) count += NonFinite(t);
    for (float r : level.rmse) count += NonFinite(r);
    const FitLevelStats& s = level.stats;
    for (double v : {s.rmse_mean, s.rmse_p95, s.rmse_max, s.relative_rmse}) count += std::isfinite(v) ? 0 : 1;
  }
  return count;
}

FitFallbacks CountFallbacks(const FittedFabric& fit) {
  FitFallbacks counts;
  for (const FittedLevel& level : fit.levels) {
    const FitLevelStats& s = level.stats;
    counts.fallbacks += s.fewer_lobes + s.diffuse_only;
    counts.fitted += uint64_t{s.resolution} * s.resolution - s.empty;
  }
  return counts;
}

ImageComparison CompareMethods(const std::string& regime, const Image& svbrdf, const Image& reference,
                               const ComparisonBounds& bounds, const std::string& method) {
  Figure(regime, method, "frame_nonfinite", static_cast<double>(NonFiniteCount(svbrdf)), AtMost(0));
  Figure(regime, "reference", "frame_nonfinite", static_cast<double>(NonFiniteCount(reference)), AtMost(0));
  const ImageComparison comparison = CompareImages(svbrdf, reference);
  Figure(regime, method, "psnr_db", comparison.psnr_db, bounds.psnr_db);
  Figure(regime, method, "ssim", comparison.ssim, Unbounded());
  const double mean_ratio = MeanRed(svbrdf) / MeanRed(reference);
  Figure(regime, method, "mean_ratio", mean_ratio, Unbounded());
  Figure(regime, method, "mean_ratio_error", std::abs(mean_ratio - 1.0), bounds.mean_ratio_error);
  return comparison;
}

double LobePeakLog10Ratio(const FittedFabric& fit) {
  constexpr double kTwoPi = 6.283185307179586;
  double worst = -INFINITY;
  for (const FittedLevel& level : fit.levels) {
    for (const LafortuneBrdf& brdf : level.brdfs) {
      for (uint32_t i = 0; i < brdf.lobe_count; ++i) {
        const LafortuneLobe& lobe = brdf.lobes[i];
        for (int c = 0; c < 3; ++c) {
          const double coefficient = std::max({std::abs(lobe.cx[c]), std::abs(lobe.cy[c]), std::abs(lobe.cz[c])});
          if (coefficient == 0.0) continue;
          const double n = lobe.n[c];
          worst = std::max(worst, (n * std::log(coefficient) - std::log((n + 2.0) / kTwoPi)) / std::log(10.0));
        }
      }
    }
  }
  return worst;
}

void CheckFit(const std::string& regime, const FittedFabric& fit, Bound fallback_fraction) {
  Figure(regime, "fit", "asset_nonfinite", static_cast<double>(NonFiniteCount(fit)), AtMost(0));
  // 1 = ten times the energy-conserving peak, where the fit rejects a lobe
  // (core/fit/texel_fit.cpp LobePeaksBounded); a fully diffuse asset has no lobe (-inf,
  // reported as -99).
  const double peak = LobePeakLog10Ratio(fit);
  Figure(regime, "fit", "lobe_peak_log10_ratio_max", std::isfinite(peak) ? peak : -99.0, AtMost(1.0 + 1e-4));
  const FitFallbacks fallbacks = CountFallbacks(fit);
  Figure(regime, "fit", "fallback_texels", static_cast<double>(fallbacks.fallbacks), Unbounded());
  Figure(regime, "fit", "fallback_fraction", fallbacks.fraction(), fallback_fraction);
  Figure(regime, "fit", "relative_rmse_level0", fit.levels.at(0).stats.relative_rmse, Unbounded());
}

ImageComparison CheckRegime(const std::string& regime, const ComparisonOptions& options,
                            const ComparisonBounds& bounds, Bound fallback_fraction) {
  const v1::SceneSpec scene = MakeComparisonScene(options);
  const ImageComparison comparison = CompareMethods(regime, RenderSvbrdf(scene), RenderReference(scene), bounds);
  CheckFit(regime, FitOf(scene.objects(0).fabric()), fallback_fraction);
  return comparison;
}

}  // namespace loom::testing
