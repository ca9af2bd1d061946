#pragma once
// Fitting a whole fabric tile (Daubert 2001 §5, §5.1): the BRDF array of every
// mip level from one set of radiance samples.
//
// Level 0 has one texel per sampled texel. Texel (x, y) of level k + 1 is fitted
// to the pooled raw samples of its 2×2 children at level k, which are the raw
// samples of the 2^{k+1}×2^{k+1} level-0 texels it covers: the paper's "fitted, not
// filtered" mip levels, each level seeing the same raw samples. Those of one view
// and light are pooled exactly (texel_fit.h TexelSamples), so a coarse texel costs
// what a fine one does. Its normal is its children's normals averaged, its tangent
// re-derived from that normal as acquisition derives tangents
// (core/acquire/radiance_samples.h TexelTangent), and its alpha per view the mean
// of its children's (alpha is not fitted, §5).
//
// Empty texels (no view with alpha > 0) keep status kEmpty and take their
// parent's BRDF and table, or at the top level (or without mip levels) those of
// the nearest non-empty texel of their level, tile-periodically; their alpha stays
// 0, so a renderer shows the hole, but filtering across it sees sensible values.
//
// Work. Levels are fitted coarsest first, each texel from several starts, keeping
// the fit with the least error on its samples (texel_fit.h ChannelStart): the top
// level from the paper's start and AlternativeStarts, a level between the top and
// level 0 from the paper's start and its parent's fit, level 0 from the paper's
// start alone. So a level depends on its own samples and the coarser levels' fits,
// never on a finer level's: the mip levels a scene shows come out the same (up to
// rounding) from a fit whose finest level is coarser — acquired at a lower
// resolution with proportionally more supersampling, the same rays — which is what
// lets the planner drop the levels a scene's footprint cannot show
// (core/plan/precompute_plan.h). Fitted finest first from their children's fits, as
// before asset format 5, the coarse levels inherited the fine levels' minima: the
// same 2×2 level of a far-away knit, fitted from the same samples, differed by up
// to 2 dB of frame PSNR between a 32×32 and an 8×8 finest level (docs/results/plan.md).
// Level 0 keeps the paper's start: it is most of the fit's time (a coarse texel
// costs what a fine one does), and a parent's fit as its only start led the shiny
// satin's texels into worse minima (2.3 dB lower PSNR close up). Within a level
// each (texel, channel) is an independent work item (texel_fit.h), spread over
// every core by ParallelFor. The result does not depend on the thread count.

#include <cstdint>
#include <functional>
#include <string_view>
#include <vector>

#include "core/acquire/radiance_samples.h"
#include "core/fit/lafortune_brdf.h"
#include "core/fit/texel_fit.h"
#include "loom/v1/precompute.pb.h"

namespace loom {

struct FitLevelStats {
  uint32_t level = 0;
  uint32_t resolution = 0;
  uint64_t samples = 0;          // valid (texel, view, light) samples pooled by the level's fits
  double rmse_mean = 0.0;        // per-texel RMSE over the non-empty texels: mean, 95th percentile, max
  double rmse_p95 = 0.0;
  double rmse_max = 0.0;
  double relative_rmse = 0.0;    // RMSE over every sample of the level / their mean radiance
  uint32_t black = 0;            // texel counts per status
  uint32_t fewer_lobes = 0;
  uint32_t diffuse_only = 0;
  uint32_t empty = 0;
  // Averages over the non-empty texels: LM iterations summed over a texel's
  // channels, alternations the most of any channel.
  double lm_iterations_per_texel = 0.0;
  double mean_alternations = 0.0;
  double fit_seconds = 0.0;      // wall time of the level's fit
};

struct FittedLevel {
  uint32_t resolution = 0;
  // Texel (x, y) is index y·resolution + x; per (texel, view) arrays are
  // texel-major like RadianceSamples.
  std::vector<LafortuneBrdf> brdfs;
  std::vector<glm::vec3> lut;  // T at [texel·V + view]
  std::vector<float> alpha;    // at [texel·V + view]
  std::vector<glm::vec3> normals;
  std::vector<glm::vec3> tangents;
  std::vector<float> rmse;
  std::vector<TexelFitStatus> status;
  FitLevelStats stats;
};

struct FittedFabric {
  uint32_t lobes = 0;
  bool lookup_table = true;
  std::vector<glm::vec3> view_directions;  // the LUT's directions, HemisphereGridDirections order
  std::vector<FittedLevel> levels;         // levels[0] is the finest
  double seconds = 0.0;                    // wall time of FitFabric
  // Per view, the tile z of the plane its texels were sampled on
  // (RadianceSamples::view_heights): a renderer looks texels up where the view ray
  // crosses it, not where it meets the macro surface (tile z = 0).
  std::vector<float> view_heights;
};

// fraction in [0, 1], non-decreasing (each level's share is its share of the
// texels); stage names the step.
// Called on the calling thread; throwing from it cancels the fit.
using FitProgress = std::function<void(double fraction, std::string_view stage)>;

// Every raw sample of texel `texel` of mip level `level` (indexed at that level's
// resolution, samples.resolution >> level; the level-0 texels it covers, views with
// alpha > 0) with its directions in `frame`, those of one view and light pooled and
// weighted by their alpha (texel_fit.h TexelSamples): they share the frame.
// FitFabric fits each texel in its own frame, its children's normals averaged;
// fit_benchmark's frame search fits the same samples in other frames.
TexelSamples GatherTexelSamples(const RadianceSamples& samples, uint32_t level, size_t texel,
                                const TexelFrame& frame);

// settings: lobes, lookup_table, mip_levels, lut_change_threshold,
// max_alternations, max_lm_iterations (defaults applied here). The level count
// comes from the samples' resolution, which must be a power of two for mip levels
// (Error(kInvalidArgument) otherwise). threads = 0 uses every core.
FittedFabric FitFabric(const RadianceSamples& samples, const v1::PrecomputeSettings& settings,
                       const FitProgress& progress = {}, unsigned threads = 0);

}  // namespace loom
