#pragma once
// Fitting a whole fabric tile (Daubert 2001 §5, §5.1): the BRDF array of every
// mip level from one set of radiance samples ("fitted, not filtered" levels).
//
// Level 0 has one texel per sampled texel; texel (x, y) of level k + 1 is fitted
// to the pooled raw samples of its 2×2 children (texel_fit.h TexelSamples), its
// normal their normals averaged, its tangent re-derived as acquisition derives
// tangents, its alpha per view their mean (alpha is not fitted). Empty texels (no
// view with alpha > 0) keep status kEmpty and their alpha 0 and take their parent's
// BRDF and table (at the top level, or without mip levels, the nearest non-empty
// texel's, tile-periodically), so filtering across a hole sees sensible values.
//
// Levels are fitted coarsest first, each texel from several starts, keeping the
// least error: a level depends on its own samples and the coarser levels' fits,
// never on a finer level's, so the planner may drop the levels a scene cannot show
// (core/plan/precompute_plan.h). Within a level each (texel, channel) is an
// independent work item spread over every core; the result does not depend on the
// thread count. Why each choice: docs/methods/svbrdf.md.

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
