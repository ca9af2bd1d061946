// The fitting engine's figures (issue 4): the standard fabric fit and its
// speed-versus-accuracy points, and the derivative choice of the lobe fit.
//
//   loom_fit_benchmark --benchmark_filter=FitFabric/res:32/lobes:2/lut:1   synthetic, the standard size
//   loom_fit_benchmark --samples=/tmp/knit.samples --benchmark_filter=FitSamples
//                                                   real samples (loom-lab acquire), the same figures
//   loom_fit_benchmark --benchmark_filter=LobeSolve  analytic vs automatic derivatives
//   loom_fit_benchmark --samples=/tmp/knit.samples --benchmark_filter=TexelFrameSearch
//                                                   what fitting each texel's frame would gain
//
// Synthetic input: radiance samples of a knit-like tile, rendered from known
// per-texel Lafortune BRDFs under a coloured lookup table on bumpy normals, with
// holes and 2% multiplicative noise. Real input: a samples file, fitted with 1-3
// lobes, LUT on and off. Acquisition itself is not timed here. Relative RMSE per
// level is the fit's RMSE over a level's samples divided by their mean radiance; at
// coarse levels it includes the spread between the pooled texels, which no single
// BRDF can fit.

#include <benchmark/benchmark.h>

#include <unistd.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <random>
#include <string>
#include <string_view>
#include <tuple>
#include <vector>

#include "core/acquire/hemisphere_directions.h"
#include "core/acquire/radiance_samples.h"
#include "core/fit/fabric_asset.h"
#include "core/fit/fabric_fit.h"
#include "core/fit/lobe_cost.h"
#include "core/fit/texel_fit.h"
#include "core/util/parallel_for.h"

namespace loom {
namespace {

constexpr uint32_t kDirections = 64;

// The BRDF of texel (x, y): a sheen that varies along the yarn, like a knit's
// loops (period 8 texels).
LafortuneBrdf SyntheticBrdf(uint32_t x, uint32_t y) {
  const float u = glm::two_pi<float>() * float(x) / 8.0f, w = glm::two_pi<float>() * float(y) / 8.0f;
  LafortuneBrdf brdf;
  brdf.lobe_count = 2;
  brdf.rho = glm::vec3(0.20f, 0.12f, 0.08f) * (1.0f + 0.3f * std::sin(u) * std::cos(w));
  brdf.lobes[0] = {glm::vec3(-1.0f + 0.05f * std::sin(w)), glm::vec3(-0.8f), glm::vec3(0.9f),
                   glm::vec3(10.0f + 4.0f * std::cos(u))};
  brdf.lobes[1] = {glm::vec3(-0.7f), glm::vec3(-0.95f), glm::vec3(0.8f), glm::vec3(5.0f)};
  return brdf;
}

// `noise_floor`, if given, receives the relative RMSE of the noise alone (the
// noise-free truth against the samples), the least a level-0 fit can reach.
RadianceSamples SyntheticSamples(uint32_t resolution, double* noise_floor = nullptr) {
  double noise_squared = 0.0, radiance_sum = 0.0;
  size_t values = 0;
  RadianceSamples samples(resolution, HemisphereGridDirections(kDirections), HemisphereGridDirections(kDirections));
  for (uint32_t texel = 0; texel < samples.texel_count(); ++texel) {
    const uint32_t x = texel % resolution, y = texel / resolution;
    const float u = glm::two_pi<float>() * float(x) / 8.0f, w = glm::two_pi<float>() * float(y) / 8.0f;
    const glm::vec3 normal = glm::normalize(glm::vec3(0.3f * std::sin(u), 0.3f * std::cos(w), 1.0f));
    samples.normals[texel] = normal;
    samples.tangents[texel] = TexelTangent(normal);
    const TexelFrame frame(normal, samples.tangents[texel]);
    const LafortuneBrdf brdf = SyntheticBrdf(x, y);
    std::mt19937 random(texel);
    std::normal_distribution<float> noise(1.0f, 0.02f);
    const bool gap = x % 8 == 4 && y % 8 == 4;  // a hole between loops
    for (size_t v = 0; v < samples.view_count(); ++v) {
      const glm::vec3 view = samples.view_directions[v];
      // Seen through the gap only head-on; elsewhere every view sees yarn.
      const float alpha = gap ? (view.z > 0.8f ? 0.5f : 0.0f) : 1.0f;
      samples.alpha[samples.AlphaIndex(texel, v)] = alpha;
      if (alpha == 0.0f) continue;
      const float grazing = 1.0f - view.z;
      const glm::vec3 lut(1.0f - 0.2f * grazing, 1.0f - 0.4f * grazing, 1.0f - 0.5f * grazing);
      for (size_t l = 0; l < samples.light_count(); ++l) {
        const glm::vec3 r = lut * brdf.Evaluate(frame.ToLocal(samples.light_directions[l]), frame.ToLocal(view));
        const glm::vec3 noisy = r * glm::vec3(noise(random), noise(random), noise(random));
        samples.radiance[samples.RadianceIndex(texel, v, l)] = noisy;
        noise_squared += glm::dot(noisy - r, noisy - r);
        radiance_sum += noisy.x + noisy.y + noisy.z;
        values += 3;
      }
    }
  }
  if (noise_floor != nullptr) *noise_floor = std::sqrt(noise_squared / values) / (radiance_sum / values);
  return samples;
}

// What storing the asset in half floats costs: the RMSE between level 0 of `a` and
// `b` rendered (T · f_1) for every texel, view and light, relative to a's mean.
double RenderDifference(const FittedFabric& a, const FittedFabric& b, const RadianceSamples& samples) {
  const FittedLevel& x = a.levels[0];
  const FittedLevel& y = b.levels[0];
  const size_t views = samples.view_count();
  double squared = 0.0, sum = 0.0;
  for (size_t texel = 0; texel < x.brdfs.size(); ++texel) {
    const TexelFrame frame_x(x.normals[texel], x.tangents[texel]);
    const TexelFrame frame_y(y.normals[texel], y.tangents[texel]);
    for (size_t v = 0; v < views; ++v) {
      const glm::vec3 view = samples.view_directions[v];
      for (const glm::vec3& l : samples.light_directions) {
        const glm::dvec3 rx =
            x.lut[texel * views + v] * x.brdfs[texel].Evaluate(frame_x.ToLocal(l), frame_x.ToLocal(view));
        const glm::dvec3 ry =
            y.lut[texel * views + v] * y.brdfs[texel].Evaluate(frame_y.ToLocal(l), frame_y.ToLocal(view));
        squared += glm::dot(rx - ry, rx - ry);
        sum += rx.x + rx.y + rx.z;
      }
    }
  }
  const double values = 3.0 * x.brdfs.size() * views * samples.light_count();
  return std::sqrt(squared / values) / (sum / values);
}

// Fits `samples` with `lobes` lobes and the table on or off (all mip levels, every
// core) and reports the fit's figures as counters.
void FitAndReport(benchmark::State& state, const RadianceSamples& samples, int64_t lobes, int64_t lut) {
  v1::PrecomputeSettings settings;
  settings.set_lobes(static_cast<uint32_t>(lobes));
  settings.set_lookup_table(lut != 0);
  FittedFabric fabric;
  for (auto _ : state) fabric = FitFabric(samples, settings);

  size_t texels = 0;
  double iterations = 0.0, alternations = 0.0;
  for (const FittedLevel& level : fabric.levels) {
    const size_t n = size_t{level.resolution} * level.resolution;
    texels += n;
    iterations += level.stats.lm_iterations_per_texel * n;
    alternations += level.stats.mean_alternations * n;
    const std::string k = std::to_string(level.stats.level);
    state.counters["rel_rmse_L" + k] = level.stats.relative_rmse;
    state.counters["lm_iter_L" + k] = level.stats.lm_iterations_per_texel;
    state.counters["alternations_L" + k] = level.stats.mean_alternations;
    state.counters["seconds_L" + k] = level.stats.fit_seconds;
    state.counters["fallbacks_L" + k] = level.stats.fewer_lobes + level.stats.diffuse_only;
  }
  // The asset as the server caches it, in half floats (the default) and in full
  // floats, and what half floats cost in rendered radiance.
  for (const bool half : {true, false}) {
    settings.set_half_float(half);
    const std::filesystem::path directory =
        std::filesystem::temp_directory_path() / ("loom_fit_benchmark_asset_" + std::to_string(::getpid()));
    WriteFabricAsset(fabric, settings, "benchmark", directory);
    uintmax_t bytes = 0;
    for (const auto& entry : std::filesystem::directory_iterator(directory)) bytes += entry.file_size();
    state.counters[half ? "asset_bytes" : "asset_bytes_float"] = double(bytes);
    if (half) state.counters["half_rel_err_L0"] = RenderDifference(fabric, ReadFabricAsset(directory), samples);
    std::filesystem::remove_all(directory);
  }
  state.counters["texels"] = double(texels);
  state.counters["texels_per_s"] = benchmark::Counter(double(texels), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["lm_iter_per_texel"] = iterations / texels;
  state.counters["alternations"] = alternations / texels;
  state.counters["seconds"] = fabric.seconds;
}

// Args: resolution, lobes, lookup table (0/1).
void BM_FitFabric(benchmark::State& state) {
  double noise_floor = 0.0;
  const RadianceSamples samples = SyntheticSamples(static_cast<uint32_t>(state.range(0)), &noise_floor);
  FitAndReport(state, samples, state.range(1), state.range(2));
  state.counters["noise_floor"] = noise_floor;
}
// The speed-versus-accuracy points: {lobes, lookup table}, the standard first.
constexpr std::array<std::array<int64_t, 2>, 6> kModels = {{{2, 1}, {1, 0}, {1, 1}, {2, 0}, {3, 0}, {3, 1}}};

void RegisterSyntheticFits() {
  auto* benchmark = benchmark::RegisterBenchmark("BM_FitFabric", BM_FitFabric);
  benchmark->ArgNames({"res", "lobes", "lut"});
  for (const auto& [lobes, lut] : kModels) benchmark->Args({32, lobes, lut});
  benchmark->Iterations(1)->UseRealTime()->Unit(benchmark::kSecond);
}

// --- A fitted texel frame (Daubert §5: "could probably be further improved by also
// computing a new normal and tangent to best fit the input data") -------------------

// The fit of one level-0 texel's samples in the frame (normal, tangent).
TexelFit FitInFrame(const RadianceSamples& samples, size_t texel, glm::vec3 normal, glm::vec3 tangent,
                    const TexelFitOptions& options) {
  return FitTexel(GatherTexelSamples(samples, 0, texel, TexelFrame(normal, tangent)), options);
}

glm::vec3 Rotated(glm::vec3 v, glm::vec3 axis, float degrees) {
  return glm::normalize(glm::vec3(glm::rotate(glm::mat4(1.0f), glm::radians(degrees), axis) * glm::vec4(v, 0.0f)));
}

// Every `stride`-th level-0 texel fitted (`lobes` lobes, the table on) in
// acquisition's frame (its mean normal), in the flat frame (the tile's normal), and
// in the frame a pattern search finds: from acquisition's frame, rotations by
// ±step about the frame's three axes, moving to the best while it lowers the fit's
// RMSE by 0.1%, the step halved from 24° to 3°. Each rotation is a whole texel fit,
// so this measures what fitting the frame could gain, at ~50 fits a texel; it is
// not how Loom fits. Relative RMSE as in FitAndReport, over the chosen texels.
void SearchTexelFrames(benchmark::State& state, const RadianceSamples& samples, int64_t lobes, int64_t stride) {
  TexelFitOptions options;
  options.lobes = static_cast<uint32_t>(lobes);
  std::vector<size_t> texels;
  for (size_t texel = 0; texel < samples.texel_count(); texel += static_cast<size_t>(stride)) texels.push_back(texel);
  struct Result {
    double weight = 0.0, mean = 0.0, stored = 0.0, flat = 0.0, searched = 0.0, fits = 0.0, normal_moved = 0.0;
  };
  std::vector<Result> results(texels.size());
  for (auto _ : state) {
    ParallelFor(texels.size(), 0, [&](size_t i, unsigned) {
      const size_t texel = texels[i];
      glm::vec3 normal = samples.normals[texel], tangent = samples.tangents[texel];
      const TexelFit fit = FitInFrame(samples, texel, normal, tangent, options);
      Result& result = results[i];
      result = {fit.weight, fit.mean_radiance, fit.rmse,
                FitInFrame(samples, texel, {0, 0, 1}, {1, 0, 0}, options).rmse, fit.rmse, 2.0, 0.0};
      for (const float step : {24.0f, 12.0f, 6.0f, 3.0f}) {
        for (bool moved = true; moved;) {
          const glm::vec3 axes[3] = {tangent, glm::cross(normal, tangent), normal};
          glm::vec3 best_normal = normal, best_tangent = tangent;
          double best = result.searched;
          for (const glm::vec3& axis : axes) {
            for (const float sign : {-1.0f, 1.0f}) {
              const glm::vec3 n = Rotated(normal, axis, sign * step), t = Rotated(tangent, axis, sign * step);
              if (n.z < 0.05f) continue;  // keep the frame facing up
              const double rmse = FitInFrame(samples, texel, n, t, options).rmse;
              result.fits += 1.0;
              if (rmse < best) std::tie(best, best_normal, best_tangent) = std::tuple(rmse, n, t);
            }
          }
          moved = best < 0.999 * result.searched;
          if (moved) std::tie(result.searched, normal, tangent) = std::tuple(best, best_normal, best_tangent);
        }
      }
      result.normal_moved = glm::degrees(std::acos(std::min(1.0f, glm::dot(normal, samples.normals[texel]))));
    });
  }
  double weight = 0.0, radiance = 0.0, stored = 0.0, flat = 0.0, searched = 0.0, fits = 0.0, moved = 0.0;
  for (const Result& r : results) {
    weight += r.weight;
    radiance += r.mean * r.weight;
    stored += r.stored * r.stored * r.weight;
    flat += r.flat * r.flat * r.weight;
    searched += r.searched * r.searched * r.weight;
    fits += r.fits;
    moved += r.normal_moved;
  }
  auto relative = [&](double squared) { return std::sqrt(squared * weight) / radiance; };
  state.counters["texels"] = double(texels.size());
  state.counters["rel_rmse_stored_frame"] = relative(stored);
  state.counters["rel_rmse_flat_frame"] = relative(flat);
  state.counters["rel_rmse_searched_frame"] = relative(searched);
  state.counters["psnr_gain_db"] = 10.0 * std::log10(stored / searched);
  state.counters["fits_per_texel"] = fits / double(texels.size());
  state.counters["normal_moved_deg"] = moved / double(texels.size());
}

// The samples file is read once, when the first of its benchmarks runs.
void RegisterSampleFits(const std::string& path) {
  auto samples = std::make_shared<std::optional<RadianceSamples>>();
  auto* benchmark = benchmark::RegisterBenchmark("BM_FitSamples", [path, samples](benchmark::State& state) {
    if (!*samples) *samples = ReadRadianceSamples(path);
    FitAndReport(state, **samples, state.range(0), state.range(1));
  });
  benchmark->ArgNames({"lobes", "lut"});
  for (const auto& [lobes, lut] : kModels) benchmark->Args({lobes, lut});
  benchmark->Iterations(1)->UseRealTime()->Unit(benchmark::kSecond);

  auto* frames = benchmark::RegisterBenchmark("BM_TexelFrameSearch", [path, samples](benchmark::State& state) {
    if (!*samples) *samples = ReadRadianceSamples(path);
    SearchTexelFrames(state, **samples, state.range(0), state.range(1));
  });
  frames->ArgNames({"lobes", "stride"});
  for (const int64_t lobes : {1, 2, 3}) frames->Args({lobes, 7});
  frames->Iterations(1)->UseRealTime()->Unit(benchmark::kSecond);
}

// --- Analytic vs automatic derivatives for one lobe solve -------------------------------

// One level-0 texel of the synthetic tile (64 views × 64 lights), red channel, T = 1.
struct SolveInput {
  TexelGeometry geometry;
  std::vector<double> radiance;
  std::vector<double> lut;
};

SolveInput MakeSolveInput() {
  const RadianceSamples samples = SyntheticSamples(8);
  const size_t texel = 3 * 8 + 1;
  const TexelSamples texel_samples =
      GatherTexelSamples(samples, 0, texel, TexelFrame(samples.normals[texel], samples.tangents[texel]));
  return {texel_samples.geometry(), texel_samples.Channel(0), std::vector<double>(kDirections, 1.0)};
}

constexpr uint32_t kLobes = 2;
constexpr int kParameters = 1 + 4 * kLobes;

// Every residual of the texel in one automatically differentiated block.
struct AllResiduals {
  const SolveInput* input;
  template <typename T>
  bool operator()(const T* x, T* residuals) const {
    for (size_t s = 0; s < input->geometry.size(); ++s) {
      residuals[s] = input->geometry.cosines[s] * LafortuneChannel(x, kLobes, input->geometry.arguments[s]) -
                     input->radiance[s];
    }
    return true;
  }
};

// One residual per block, the textbook Ceres layout.
struct OneResidual {
  const SolveInput* input;
  size_t s;
  template <typename T>
  bool operator()(const T* x, T* residual) const {
    residual[0] = input->geometry.cosines[s] * LafortuneChannel(x, kLobes, input->geometry.arguments[s]) -
                  input->radiance[s];
    return true;
  }
};

enum Derivatives { kAnalytic, kAutoOneBlock, kAutoPerSample };

void BM_LobeSolve(benchmark::State& state) {
  const SolveInput input = MakeSolveInput();
  const auto derivatives = static_cast<Derivatives>(state.range(0));
  const ceres::Solver::Options options = LobeSolverOptions(50);
  const std::vector<double> start = StartParameters(input.geometry, input.radiance, kLobes);
  ceres::Solver::Summary summary;
  for (auto _ : state) {
    std::vector<double> x = start;
    ceres::Problem problem;
    AddLobeParameterBounds(problem, x.data(), kLobes);
    switch (derivatives) {
      case kAnalytic:
        problem.AddResidualBlock(new LobeCost(input.geometry, input.radiance, input.lut, kLobes), nullptr, x.data());
        break;
      case kAutoOneBlock:
        problem.AddResidualBlock(new ceres::AutoDiffCostFunction<AllResiduals, ceres::DYNAMIC, kParameters>(
                                     new AllResiduals{&input}, static_cast<int>(input.geometry.size())),
                                 nullptr, x.data());
        break;
      case kAutoPerSample:
        for (size_t s = 0; s < input.geometry.size(); ++s) {
          problem.AddResidualBlock(
              new ceres::AutoDiffCostFunction<OneResidual, 1, kParameters>(new OneResidual{&input, s}), nullptr,
              x.data());
        }
        break;
    }
    ceres::Solve(options, &problem, &summary);
    benchmark::DoNotOptimize(x.data());
  }
  state.counters["lm_iterations"] = summary.num_successful_steps + summary.num_unsuccessful_steps;
  state.counters["final_cost"] = summary.final_cost;
  state.counters["samples"] = double(input.geometry.size());
}
BENCHMARK(BM_LobeSolve)
    ->ArgName("derivatives")
    ->Arg(kAnalytic)
    ->Arg(kAutoOneBlock)
    ->Arg(kAutoPerSample)
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace loom

// Google Benchmark's main, plus --samples=PATH (a file from loom-lab acquire) for
// the BM_FitSamples benchmarks.
int main(int argc, char** argv) {
  constexpr std::string_view kSamplesFlag = "--samples=";
  std::vector<char*> arguments;
  for (int i = 0; i < argc; ++i) {
    const std::string_view argument = argv[i];
    if (argument.starts_with(kSamplesFlag)) {
      loom::RegisterSampleFits(std::string(argument.substr(kSamplesFlag.size())));
    } else {
      arguments.push_back(argv[i]);
    }
  }
  loom::RegisterSyntheticFits();
  int count = static_cast<int>(arguments.size());
  benchmark::Initialize(&count, arguments.data());
  if (benchmark::ReportUnrecognizedArguments(count, arguments.data())) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
