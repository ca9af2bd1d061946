#include "core/fit/fabric_fit.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <string>

#include "core/spec/defaults.h"
#include "core/util/error.h"
#include "core/util/parallel_for.h"
#include "core/util/stopwatch.h"
#include "core/util/vector_math.h"

namespace loom {
namespace {

uint32_t LevelCount(uint32_t resolution, v1::MipLevels mip_levels) {
  if (mip_levels == v1::MIP_LEVELS_NONE) return 1;
  if (!std::has_single_bit(resolution)) {
    throw Error(ErrorCode::kInvalidArgument, "fitting mip levels needs a power-of-two resolution, not " +
                                                 std::to_string(resolution));
  }
  return static_cast<uint32_t>(std::countr_zero(resolution)) + 1;
}

FittedLevel FinestLevel(const RadianceSamples& samples) {
  FittedLevel level;
  level.resolution = samples.resolution;
  level.normals = samples.normals;
  level.tangents = samples.tangents;
  level.alpha = samples.alpha;
  return level;
}

// Per level-0 texel, the sum of the normals its rays hit, in units of the
// texel's rays: acquisition's mean normal scaled by its length and by the
// texel's coverage summed over the views. Summed over a mip texel's children it
// is the sum over every ray under it, whatever resolution they were acquired at.
std::vector<glm::dvec3> HitNormalSums(const RadianceSamples& samples) {
  std::vector<glm::dvec3> sums(samples.texel_count());
  for (size_t texel = 0; texel < sums.size(); ++texel) {
    double coverage = 0.0;
    for (size_t v = 0; v < samples.view_count(); ++v) coverage += samples.alpha[samples.AlphaIndex(texel, v)];
    sums[texel] = glm::dvec3(samples.normals[texel]) * double{samples.normal_lengths[texel]} * coverage;
  }
  return sums;
}

// Level k + 1's geometry from level k's (§5.1): normals averaged over the rays
// under each texel (`normal_sums`, level k's on entry, level k + 1's on return;
// acquisition's normal is the mean over the rays that hit, so a mostly empty or
// incoherent child must not count as a full one), tangents re-derived, alpha per
// view averaged.
FittedLevel CoarserLevel(const FittedLevel& fine, std::vector<glm::dvec3>& normal_sums, size_t views) {
  FittedLevel coarse;
  coarse.resolution = fine.resolution / 2;
  const size_t texels = size_t{coarse.resolution} * coarse.resolution;
  coarse.normals.resize(texels);
  coarse.tangents.resize(texels);
  coarse.alpha.assign(texels * views, 0.0f);
  std::vector<glm::dvec3> coarse_sums(texels, glm::dvec3(0.0));
  for (size_t texel = 0; texel < texels; ++texel) {
    const size_t x = texel % coarse.resolution, y = texel / coarse.resolution;
    for (size_t child_y = 2 * y; child_y < 2 * y + 2; ++child_y) {
      for (size_t child_x = 2 * x; child_x < 2 * x + 2; ++child_x) {
        const size_t child = child_y * fine.resolution + child_x;
        coarse_sums[texel] += normal_sums[child];
        for (size_t v = 0; v < views; ++v) coarse.alpha[texel * views + v] += 0.25f * fine.alpha[child * views + v];
      }
    }
    coarse.normals[texel] = SafeNormalize(glm::vec3(coarse_sums[texel]), glm::vec3(0, 0, 1));
    coarse.tangents[texel] = TexelTangent(coarse.normals[texel]);
  }
  normal_sums = std::move(coarse_sums);
  return coarse;
}

// The start candidate of a coarse texel's fit, channel c (texel_fit.h
// ChannelStart): its parent's fit, none if the parent is empty.
std::vector<ChannelStart> ParentStart(const std::vector<std::array<ChannelFit, 3>>& parents, uint32_t resolution,
                                      size_t texel, int c) {
  const size_t x = texel % resolution, y = texel / resolution;
  const ChannelFit& parent = parents[(y / 2) * (resolution / 2) + x / 2][c];
  if (parent.status == TexelFitStatus::kEmpty) return {};
  return {ChannelStart{parent.parameters, parent.lut}};
}

// Stores a texel's combined fit in its level.
void StoreTexel(FittedLevel& level, size_t texel, size_t views, const TexelFit& fit) {
  level.brdfs[texel] = fit.brdf;
  std::copy(fit.lut.begin(), fit.lut.end(), level.lut.begin() + texel * views);
  level.rmse[texel] = static_cast<float>(fit.rmse);
  level.status[texel] = fit.status;
}

// Copies texel `from`'s fitted values (not its alpha, normal or status) to `to`.
void CopyFit(const FittedLevel& source, size_t from, FittedLevel& target, size_t to, size_t views) {
  target.brdfs[to] = source.brdfs[from];
  std::copy_n(source.lut.begin() + from * views, views, target.lut.begin() + to * views);
}

// The nearest texel of `level` that is not empty, by tile-periodic distance (ties
// to the lowest index); `texel` itself if there is none.
size_t NearestNonEmpty(const FittedLevel& level, size_t texel) {
  const int64_t res = level.resolution;
  auto wrapped = [res](int64_t d) { return std::min(std::abs(d), res - std::abs(d)); };
  size_t best = texel;
  int64_t best_distance = INT64_MAX;
  for (size_t other = 0; other < level.status.size(); ++other) {
    if (level.status[other] == TexelFitStatus::kEmpty) continue;
    const int64_t dx = wrapped(int64_t(other % res) - int64_t(texel % res));
    const int64_t dy = wrapped(int64_t(other / res) - int64_t(texel / res));
    if (dx * dx + dy * dy < best_distance) {
      best_distance = dx * dx + dy * dy;
      best = other;
    }
  }
  return best;
}

// Top-down, so a parent is final before its children copy it.
void FillEmptyTexels(std::vector<FittedLevel>& levels, size_t views) {
  for (size_t k = levels.size(); k-- > 0;) {
    FittedLevel& level = levels[k];
    for (size_t texel = 0; texel < level.status.size(); ++texel) {
      if (level.status[texel] != TexelFitStatus::kEmpty) continue;
      if (k + 1 < levels.size()) {
        const size_t x = texel % level.resolution, y = texel / level.resolution;
        CopyFit(levels[k + 1], (y / 2) * levels[k + 1].resolution + x / 2, level, texel, views);
      } else if (const size_t nearest = NearestNonEmpty(level, texel); nearest != texel) {
        CopyFit(level, nearest, level, texel, views);
      }
    }
  }
}

FitLevelStats LevelStats(uint32_t k, const FittedLevel& level, const std::vector<TexelFit>& fits, double seconds) {
  FitLevelStats stats;
  stats.level = k;
  stats.resolution = level.resolution;
  stats.fit_seconds = seconds;
  std::vector<double> rmse;
  double squared_error = 0.0, radiance = 0.0, weight = 0.0;
  for (const TexelFit& fit : fits) {
    stats.samples += fit.samples;
    switch (fit.status) {
      case TexelFitStatus::kBlack: ++stats.black; break;
      case TexelFitStatus::kOk: break;
      case TexelFitStatus::kFewerLobes: ++stats.fewer_lobes; break;
      case TexelFitStatus::kDiffuseOnly: ++stats.diffuse_only; break;
      case TexelFitStatus::kEmpty: ++stats.empty; continue;
    }
    stats.lm_iterations_per_texel += fit.lm_iterations;
    stats.mean_alternations += fit.alternations;
    rmse.push_back(fit.rmse);
    squared_error += fit.rmse * fit.rmse * fit.weight;
    radiance += fit.mean_radiance * fit.weight;
    weight += fit.weight;
  }
  if (!rmse.empty()) {
    stats.lm_iterations_per_texel /= rmse.size();
    stats.mean_alternations /= rmse.size();
    std::sort(rmse.begin(), rmse.end());
    for (double r : rmse) stats.rmse_mean += r / rmse.size();
    stats.rmse_p95 = rmse[std::min(rmse.size() - 1, static_cast<size_t>(std::ceil(0.95 * rmse.size())) - 1)];
    stats.rmse_max = rmse.back();
  }
  if (radiance > 0.0) stats.relative_rmse = std::sqrt(squared_error * weight) / radiance;
  return stats;
}

}  // namespace

TexelSamples GatherTexelSamples(const RadianceSamples& samples, uint32_t level, size_t texel,
                                const TexelFrame& frame) {
  const size_t views = samples.view_count(), lights = samples.light_count();
  std::vector<glm::vec3> local_lights(lights);
  for (size_t l = 0; l < lights; ++l) local_lights[l] = frame.ToLocal(samples.light_directions[l]);

  const size_t span = size_t{1} << level;
  const size_t resolution = samples.resolution >> level;
  const size_t x0 = (texel % resolution) * span, y0 = (texel / resolution) * span;
  std::vector<size_t> covered;  // the level-0 texels it covers
  for (size_t y = y0; y < y0 + span; ++y) {
    for (size_t x = x0; x < x0 + span; ++x) covered.push_back(y * samples.resolution + x);
  }
  TexelSamples result(static_cast<uint32_t>(views));
  result.Reserve(views * lights);
  std::vector<size_t> seen;  // the covered texels with alpha > 0 for a view
  std::vector<float> coverages;  // their alpha
  std::vector<glm::vec3> pooled;
  for (size_t v = 0; v < views; ++v) {
    seen.clear();
    coverages.clear();
    for (size_t child : covered) {
      const float alpha = samples.alpha[samples.AlphaIndex(child, v)];
      if (alpha <= 0.0f) continue;
      seen.push_back(child);
      coverages.push_back(alpha);
    }
    if (seen.empty()) continue;
    const glm::vec3 local_view = frame.ToLocal(samples.view_directions[v]);
    for (size_t l = 0; l < lights; ++l) {
      pooled.clear();
      for (size_t child : seen) pooled.push_back(samples.radiance[samples.RadianceIndex(child, v, l)]);
      result.AddPooled(local_lights[l], local_view, static_cast<uint32_t>(v), pooled, coverages);
    }
  }
  return result;
}

FittedFabric FitFabric(const RadianceSamples& samples, const v1::PrecomputeSettings& settings,
                       const FitProgress& progress, unsigned threads) {
  const Stopwatch total;
  const v1::PrecomputeSettings resolved = WithDefaults(settings);
  const TexelFitOptions options = MakeTexelFitOptions(resolved);
  const size_t views = samples.view_count();

  FittedFabric fabric;
  fabric.lobes = options.lobes;
  fabric.lookup_table = options.lookup_table;
  fabric.view_directions = samples.view_directions;
  fabric.view_heights = samples.view_heights;
  const uint32_t level_count = LevelCount(samples.resolution, resolved.mip_levels());
  fabric.levels.push_back(FinestLevel(samples));
  std::vector<glm::dvec3> normal_sums = HitNormalSums(samples);
  for (uint32_t k = 1; k < level_count; ++k) {
    fabric.levels.push_back(CoarserLevel(fabric.levels.back(), normal_sums, views));
  }

  // Level by level, coarsest first (see the header). Within a level every
  // (texel, channel) is one work item.
  std::vector<std::vector<std::array<ChannelFit, 3>>> channel_fits(level_count);
  std::vector<double> level_seconds(level_count, 0.0);
  // A level's share of the progress is its share of the texels: with pooled
  // samples (GatherTexelSamples) a coarse texel costs about what a fine one does.
  double total_texels = 0.0;
  for (const FittedLevel& level : fabric.levels) total_texels += double(level.resolution) * level.resolution;
  double texels_done = 0.0;
  for (uint32_t k = level_count; k-- > 0;) {
    const Stopwatch level_time;
    const uint32_t resolution = fabric.levels[k].resolution;
    const size_t texels = size_t{resolution} * resolution;
    const std::string stage = "fitting level " + std::to_string(k);
    channel_fits[k].resize(texels);
    if (progress) progress(texels_done / total_texels, stage);
    ParallelFor(
        texels * 3, threads,
        [&](size_t item, unsigned) {
          const size_t texel = item / 3;
          const int c = static_cast<int>(item % 3);
          const FittedLevel& level = fabric.levels[k];
          const TexelSamples texel_samples =
              GatherTexelSamples(samples, k, texel, TexelFrame(level.normals[texel], level.tangents[texel]));
          const std::vector<ChannelStart> starts =
              k == 0 ? std::vector<ChannelStart>()
              : k + 1 < level_count ? ParentStart(channel_fits[k + 1], resolution, texel, c)
                                    : AlternativeStarts(texel_samples, c, options.lobes);
          channel_fits[k][texel][c] = FitTexelChannel(texel_samples, c, options, starts);
        },
        [&](size_t done) {
          if (progress) progress((texels_done + double(done) / 3) / total_texels, stage);
        });
    texels_done += double(texels);
    level_seconds[k] = level_time.Seconds();
  }

  for (uint32_t k = 0; k < level_count; ++k) {
    FittedLevel& level = fabric.levels[k];
    const size_t texels = channel_fits[k].size();
    level.brdfs.resize(texels);
    level.lut.resize(texels * views);
    level.rmse.resize(texels);
    level.status.resize(texels);
    std::vector<TexelFit> fits(texels);
    for (size_t texel = 0; texel < texels; ++texel) {
      fits[texel] = CombineChannelFits(channel_fits[k][texel], options.lobes);
      StoreTexel(level, texel, views, fits[texel]);
    }
    level.stats = LevelStats(k, level, fits, level_seconds[k]);
  }
  if (progress) progress(1.0, "filling empty texels");
  FillEmptyTexels(fabric.levels, views);
  fabric.seconds = total.Seconds();
  return fabric;
}

}  // namespace loom
