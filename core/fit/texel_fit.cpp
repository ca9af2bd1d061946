#include "core/fit/texel_fit.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "core/spec/defaults.h"

namespace loom {
namespace {

constexpr uint32_t kStartExponent = 10;
// The start lobes' peak as a fraction of ρ: "a moderate specular highlight".
constexpr double kStartPeakFraction = 0.5;
constexpr double kStartAnisotropy = 1.22;
// AlternativeStarts' broad lobes.
constexpr double kBroadStartExponent = 3.0;
// T beyond this means the model is numerically zero for the view; eq. 4 would only
// amplify noise.
constexpr double kMaxLut = 1e4;

size_t ParameterCount(uint32_t lobes) { return 1 + 4 * size_t{lobes}; }

bool AllFinite(const std::vector<double>& values) {
  return std::all_of(values.begin(), values.end(), [](double v) { return std::isfinite(v); });
}

// The value of channel parameters x (lobes lobes) for sample s, T excluded.
double Model(const TexelGeometry& geometry, size_t s, const double* x, uint32_t lobes) {
  return geometry.cosines[s] * LafortuneChannel(x, lobes, geometry.arguments[s]);
}

double SquaredError(const TexelGeometry& geometry, const std::vector<double>& radiance, const double* x,
                    uint32_t lobes, const std::vector<double>& lut) {
  double sum = 0.0;
  for (size_t s = 0; s < geometry.size(); ++s) {
    const double e = lut[geometry.views[s]] * Model(geometry, s, x, lobes) - radiance[s];
    sum += e * e;
  }
  return sum;
}

// Eq. 4 for every view with samples: T* = ⟨f, r⟩ / ⟨f, f⟩, clamped to [0, kMaxLut];
// a view whose model is (numerically) zero keeps its T. Then the scale is fixed:
// T · f_1 is unchanged by T → T/s, ρ → s·ρ, C_i → s^{1/N_i}·C_i, and s = mean T
// makes the table's mean 1, so f_1 alone approximates the view-averaged BRDF (what a
// renderer without the table, or a coarse level, can use) and T stays near 1,
// where half floats are most precise.
//
// The step T → T* is shortened, if need be, so that the table changes (mean |ΔT|
// after the scale is fixed) by no more than `max_change`, the previous round's
// change. Each view's error is a convex quadratic in its T with its minimum on
// [0, kMaxLut] at T*, so any point of the segment lowers the error as eq. 4 does;
// the full step can be longer than the last one when the lobe fit moved to another
// valley, and the paper's stopping rule (the table has settled) needs a change
// that shrinks. Returns the mean |ΔT| over the views with samples.
double UpdateLut(const TexelGeometry& geometry, const std::vector<double>& radiance, std::vector<double>& x,
                 uint32_t lobes, std::vector<double>& lut, double max_change) {
  std::vector<double> fr(lut.size(), 0.0), ff(lut.size(), 0.0);
  std::vector<bool> seen(lut.size(), false);
  for (size_t s = 0; s < geometry.size(); ++s) {
    const double f = Model(geometry, s, x.data(), lobes);
    fr[geometry.views[s]] += f * radiance[s];
    ff[geometry.views[s]] += f * f;
    seen[geometry.views[s]] = true;
  }
  std::vector<double> target = lut;
  size_t views = 0;
  for (size_t v = 0; v < lut.size(); ++v) {
    if (!seen[v]) continue;
    if (ff[v] > 1e-30) target[v] = std::clamp(fr[v] / ff[v], 0.0, kMaxLut);
    ++views;
  }
  if (views == 0) return 0.0;
  // The table a fraction `step` of the way to T*, its scale fixed (the mean
  // over the views with samples, 0 if the table is all zero), and its change.
  std::vector<double> stepped(lut.size());
  double mean = 0.0;
  auto take_step = [&](double step) {
    mean = 0.0;
    for (size_t v = 0; v < lut.size(); ++v) {
      stepped[v] = lut[v] + step * (target[v] - lut[v]);
      if (seen[v]) mean += stepped[v];
    }
    mean /= views;
    double change = 0.0;
    for (size_t v = 0; v < lut.size(); ++v) {
      if (!seen[v]) continue;
      if (mean > 0.0) stepped[v] /= mean;
      change += std::abs(stepped[v] - lut[v]);
    }
    return change / views;
  };
  double change = take_step(1.0);
  if (change > max_change) {
    // The change grows with the step (from 0 at no step), so bisection finds the
    // longest step within the cap.
    double shortest = 0.0, longest = 1.0;
    for (int i = 0; i < 40; ++i) {
      const double step = 0.5 * (shortest + longest);
      (take_step(step) <= max_change ? shortest : longest) = step;
    }
    change = take_step(shortest);
  }
  if (mean > 0.0) {
    // The bounds hold the solver's start feasible; a gauge step that would leave
    // them is cut short there, which a following solve corrects.
    x[0] = std::min(x[0] * mean, kMaxDiffuse);
    for (uint32_t i = 0; i < lobes; ++i) {
      const double scale = std::pow(mean, 1.0 / x[4 + 4 * i]);
      for (int k = 1; k <= 3; ++k) {
        x[k + 4 * i] = std::clamp(x[k + 4 * i] * scale, -kMaxLobeCoefficient, kMaxLobeCoefficient);
      }
    }
  }
  lut = std::move(stepped);
  return change;
}

// Whether every lobe of channel parameters x stays within kMaxLobePeakRatio of the
// energy-conserving peak. A lobe's largest value over the hemisphere is
// max_k |C_k|^N (l and v both along the axis of the largest |C_k|); a normalised
// cosine lobe of exponent N that reflects all the light it receives peaks at
// (N + 2)/2π. The fit sees the lobe only at the sampled direction pairs, so with few
// directions (a 2×2 grid) or a highlight narrower than the grid it can place a
// spike of 10^100 between them, which renders as a highlight hundreds of times too
// bright (docs/stability.md). Such a fit is treated as failed: fewer lobes.
bool LobePeaksBounded(const std::vector<double>& x, uint32_t lobes) {
  constexpr double kMaxLobePeakRatio = 10.0;
  constexpr double kTwoPi = 6.283185307179586;
  for (uint32_t i = 0; i < lobes; ++i) {
    const double* lobe = x.data() + 1 + 4 * i;
    const double c = std::max({std::abs(lobe[0]), std::abs(lobe[1]), std::abs(lobe[2])});
    if (c == 0.0) continue;
    const double n = lobe[3];
    if (n * std::log(c) > std::log(kMaxLobePeakRatio * (n + 2.0) / kTwoPi)) return false;
  }
  return true;
}

// The layout of `lobes` lobes with the ones from `from` on switched off.
void SwitchOffLobes(std::vector<double>& x, uint32_t from, uint32_t lobes) {
  x.resize(ParameterCount(lobes), 0.0);
  for (uint32_t i = from; i < lobes; ++i) {
    std::fill_n(x.begin() + 1 + 4 * i, 3, 0.0);
    x[4 + 4 * i] = 1.0;
  }
}

// Diffuse only, in closed form. With the table, r = T(v)·ρ·l_z has the per-view
// least-squares solution s_v = ⟨l_z, r⟩/⟨l_z, l_z⟩ = T(v)·ρ; ρ = mean s_v makes
// the mean T 1. Without it, one least-squares ρ over every sample.
ChannelFit FitDiffuse(const TexelGeometry& geometry, const std::vector<double>& radiance,
                      const TexelFitOptions& options) {
  const size_t views = options.lookup_table ? geometry.view_count : 1;
  auto view_of = [&](size_t s) { return options.lookup_table ? geometry.views[s] : 0u; };
  std::vector<double> cr(views, 0.0), cc(views, 0.0);
  for (size_t s = 0; s < geometry.size(); ++s) {
    cr[view_of(s)] += geometry.cosines[s] * radiance[s];
    cc[view_of(s)] += geometry.cosines[s] * geometry.cosines[s];
  }
  std::vector<double> scale(views, 0.0);
  double rho = 0.0;
  size_t counted = 0;
  for (size_t v = 0; v < views; ++v) {
    if (!(cc[v] > 0.0)) continue;
    scale[v] = std::max(0.0, cr[v] / cc[v]);
    rho += scale[v];
    ++counted;
  }
  rho = counted > 0 ? std::min(rho / counted, kMaxDiffuse) : 0.0;

  ChannelFit fit;
  fit.status = TexelFitStatus::kDiffuseOnly;
  fit.parameters = {rho};
  SwitchOffLobes(fit.parameters, 0, options.lobes);
  fit.lut.assign(geometry.view_count, 1.0);
  if (options.lookup_table && rho > 0.0) {
    for (size_t v = 0; v < views; ++v) {
      if (cc[v] > 0.0) fit.lut[v] = std::min(scale[v] / rho, kMaxLut);
    }
  }
  // The guard of last resort: not reachable from finite samples.
  if (!AllFinite(fit.parameters) || !AllFinite(fit.lut)) {
    fit.parameters.assign(fit.parameters.size(), 0.0);
    SwitchOffLobes(fit.parameters, 0, options.lobes);
    fit.lut.assign(geometry.view_count, 1.0);
  }
  fit.squared_error = SquaredError(geometry, radiance, fit.parameters.data(), options.lobes, fit.lut);
  return fit;
}

// One Levenberg–Marquardt solve of the lobes with T fixed, warm-started from x.
// Returns whether the solution is usable; adds the iterations taken.
bool SolveLobes(LobeCost& cost, std::vector<double>& x, uint32_t lobes, const ceres::Solver::Options& options,
                uint32_t& iterations) {
  ceres::Problem::Options problem_options;
  problem_options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  AddLobeParameterBounds(problem, x.data(), lobes);
  problem.AddResidualBlock(&cost, nullptr, x.data());
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  iterations += static_cast<uint32_t>(summary.num_successful_steps + summary.num_unsuccessful_steps);
  return summary.IsSolutionUsable() && AllFinite(x);
}

// The alternation of §5 with `lobes` lobes, from `start` or the paper's start.
// Returns false if a solve failed.
//
// The paper stops once the table settles (mean |ΔT| below the threshold). A fit
// that has settled with an error still above `fallback_error` (the closed-form
// diffuse fit's) would be thrown away for fewer lobes; it keeps alternating
// instead, within the cap on alternations, while a round still lowers its error by
// kMinRoundGain: every round lowers the error (LM from the current point, then a
// step of T towards eq. 4's), and a few more rounds take some of these fits below
// the diffuse one. The table's change never grows from one round to the next
// (UpdateLut).
bool AlternateLobesAndLut(const TexelGeometry& geometry, const std::vector<double>& radiance, uint32_t lobes,
                          const TexelFitOptions& options, const ChannelStart* start, double fallback_error,
                          ChannelFit& fit) {
  constexpr double kMinRoundGain = 1e-3;
  if (start != nullptr) {
    fit.parameters = start->parameters;
    fit.lut = start->lut;
  } else {
    fit.parameters = StartParameters(geometry, radiance, lobes);
    fit.lut.assign(geometry.view_count, 1.0);
  }
  fit.alternations = 0;
  fit.lut_changes.clear();
  LobeCost cost(geometry, radiance, fit.lut, lobes);
  const ceres::Solver::Options solver = LobeSolverOptions(options.max_lm_iterations);
  double previous_error = INFINITY;
  double previous_change = INFINITY;
  while (fit.alternations < options.max_alternations) {
    ++fit.alternations;
    if (!SolveLobes(cost, fit.parameters, lobes, solver, fit.lm_iterations)) return false;
    if (!options.lookup_table) break;
    const double change = UpdateLut(geometry, radiance, fit.parameters, lobes, fit.lut, previous_change);
    previous_change = change;
    fit.lut_changes.push_back(change);
    if (change < options.lut_change_threshold) {
      const double error = SquaredError(geometry, radiance, fit.parameters.data(), lobes, fit.lut);
      if (!(error > fallback_error && error < previous_error * (1.0 - kMinRoundGain))) break;
      previous_error = error;
    }
  }
  fit.squared_error = SquaredError(geometry, radiance, fit.parameters.data(), lobes, fit.lut);
  return std::isfinite(fit.squared_error) && AllFinite(fit.lut);
}

// The channel's fit with every fallback (see the header).
ChannelFit FitChannel(const TexelGeometry& geometry, const std::vector<double>& radiance,
                      const TexelFitOptions& options, std::span<const ChannelStart> starts) {
  if (geometry.size() == 0 || std::all_of(radiance.begin(), radiance.end(), [](double r) { return r == 0.0; })) {
    ChannelFit fit = FitDiffuse(geometry, radiance, options);  // ρ = 0, lobes off, T = 1
    fit.status = geometry.size() == 0 ? TexelFitStatus::kEmpty : TexelFitStatus::kBlack;
    return fit;
  }
  const ChannelFit diffuse = FitDiffuse(geometry, radiance, options);
  // Relative slack: a lobe fit that converged onto the diffuse solution differs
  // from it only by rounding.
  const double fallback_error = diffuse.squared_error * (1.0 + 1e-9) + 1e-300;
  uint32_t iterations = 0;
  // A fit with `lobes` lobes from `start` (the paper's if null), if it solved, beats
  // the diffuse fit and keeps its peaks bounded.
  auto attempt = [&](uint32_t lobes, const ChannelStart* start) -> std::optional<ChannelFit> {
    ChannelFit fit;
    fit.lm_iterations = iterations;
    const bool solved = AlternateLobesAndLut(geometry, radiance, lobes, options, start, fallback_error, fit);
    iterations = fit.lm_iterations;
    if (!solved || fit.squared_error > fallback_error || !LobePeaksBounded(fit.parameters, lobes)) return {};
    SwitchOffLobes(fit.parameters, lobes, options.lobes);
    fit.status = lobes == options.lobes ? TexelFitStatus::kOk : TexelFitStatus::kFewerLobes;
    return fit;
  };
  // What a start whose fit with every lobe failed gets: fewer lobes from the paper's
  // start, then the diffuse fit. It does not depend on the start, so it is fitted
  // once, when a start first needs it.
  std::optional<ChannelFit> fallback;
  auto fewer_lobes = [&]() -> const ChannelFit& {
    if (fallback) return *fallback;
    for (uint32_t lobes = options.lobes - 1; lobes >= 1 && !fallback; --lobes) fallback = attempt(lobes, nullptr);
    if (!fallback) fallback = diffuse;
    return *fallback;
  };
  auto fit_from = [&](const ChannelStart* start) {
    std::optional<ChannelFit> fit = attempt(options.lobes, start);
    return fit ? std::move(*fit) : fewer_lobes();
  };
  // From the paper's start and from each given one, the fit with the least error.
  // Not merely the start closest to the samples: a parent's fit is closer than the
  // paper's start and then converges within a few iterations into a shallower
  // minimum (a knit's 1×1 level fitted worse that way).
  ChannelFit best = fit_from(nullptr);
  for (const ChannelStart& start : starts) {
    ChannelFit fit = fit_from(&start);
    if (fit.squared_error < best.squared_error) best = std::move(fit);
  }
  best.lm_iterations = iterations;
  return best;
}

}  // namespace

std::vector<double> StartParameters(const TexelGeometry& geometry, const std::vector<double>& radiance,
                                    uint32_t lobes) {
  double sum_radiance = 0.0, sum_cosine = 0.0;
  for (size_t s = 0; s < geometry.size(); ++s) {
    sum_radiance += radiance[s];
    sum_cosine += geometry.cosines[s];
  }
  const double rho = sum_cosine > 0.0 ? std::clamp(sum_radiance / sum_cosine, 0.0, kMaxDiffuse) : 0.0;
  // At the mirror direction the specular lobes' argument is ≈ c, so the peak is c^N.
  const double c = std::pow(kStartPeakFraction * rho, 1.0 / kStartExponent);
  const double start[kMaxLafortuneLobes][3] = {
      {-kStartAnisotropy * c, -c, c},  // lobe 1: C_x = 1.22·C_y
      {-c, -kStartAnisotropy * c, c},  // lobe 2: C_y = 1.22·C_x
      {c, c, c},                       // lobe 3: retro-reflection, peak at l = v
  };
  std::vector<double> x(ParameterCount(lobes));
  x[0] = rho;
  for (uint32_t i = 0; i < lobes; ++i) {
    std::copy(start[i], start[i] + 3, x.begin() + 1 + 4 * i);
    x[4 + 4 * i] = kStartExponent;
  }
  return x;
}

const char* TexelFitStatusName(TexelFitStatus status) {
  switch (status) {
    case TexelFitStatus::kBlack: return "black";
    case TexelFitStatus::kOk: return "ok";
    case TexelFitStatus::kFewerLobes: return "fallback_fewer_lobes";
    case TexelFitStatus::kDiffuseOnly: return "fallback_diffuse";
    case TexelFitStatus::kEmpty: return "empty_texel";
  }
  return "unknown";
}

TexelFitOptions MakeTexelFitOptions(const v1::PrecomputeSettings& settings) {
  const v1::PrecomputeSettings s = WithDefaults(settings);
  return {s.lobes(), s.lookup_table(), s.lut_change_threshold(), s.max_alternations(), s.max_lm_iterations()};
}

TexelSamples::TexelSamples(uint32_t view_count) { geometry_.view_count = view_count; }

void TexelSamples::Reserve(size_t count) {
  geometry_.arguments.reserve(count);
  geometry_.cosines.reserve(count);
  geometry_.views.reserve(count);
  radiance_.reserve(count);
}

void TexelSamples::Push(glm::vec3 light, glm::vec3 view, uint32_t view_index, glm::dvec3 radiance, double weight) {
  geometry_.arguments.push_back(MakeLobeArgument(light, view));
  geometry_.cosines.push_back(weight * std::max(0.0, double{light.z}));
  geometry_.views.push_back(view_index);
  radiance_.push_back(weight * radiance);
}

void TexelSamples::Add(glm::vec3 light, glm::vec3 view, uint32_t view_index, glm::vec3 radiance) {
  constexpr float kFullCoverage = 1.0f;
  AddPooled(light, view, view_index, std::span(&radiance, 1), std::span(&kFullCoverage, 1));
}

void TexelSamples::AddPooled(glm::vec3 light, glm::vec3 view, uint32_t view_index,
                             std::span<const glm::vec3> radiances, std::span<const float> coverages) {
  double weight = 0.0;
  glm::dvec3 sum(0.0);
  for (size_t j = 0; j < radiances.size(); ++j) {
    weight += coverages[j];
    sum += double{coverages[j]} * glm::dvec3(radiances[j]);
  }
  const glm::dvec3 mean = sum / weight;
  for (size_t j = 0; j < radiances.size(); ++j) {
    const glm::dvec3 d = glm::dvec3(radiances[j]) - mean;
    spread_ += double{coverages[j]} * d * d;
  }
  Push(light, view, view_index, mean, std::sqrt(weight));
  raw_count_ += radiances.size();
  raw_weight_ += weight;
  radiance_sum_ += sum;
}

std::vector<double> TexelSamples::Channel(int c) const {
  std::vector<double> values(radiance_.size());
  for (size_t s = 0; s < radiance_.size(); ++s) values[s] = radiance_[s][c];
  return values;
}

std::vector<ChannelStart> AlternativeStarts(const TexelSamples& samples, int channel, uint32_t lobes) {
  const std::vector<double> paper = StartParameters(samples.geometry(), samples.Channel(channel), lobes);
  const std::vector<double> lut(samples.view_count(), 1.0);
  const double c = paper[3];  // every lobe's C_z: the peak c^N is kStartPeakFraction·ρ
  ChannelStart retro{paper, lut};
  std::fill_n(retro.parameters.begin() + 1 + 4 * (lobes - 1), 3, c);
  ChannelStart broad{paper, lut};
  const double broad_c = std::pow(c, double(kStartExponent) / kBroadStartExponent);  // the same peak
  for (uint32_t i = 0; i < lobes; ++i) {
    for (int j = 1; j <= 3; ++j) broad.parameters[j + 4 * i] *= broad_c / c;
    broad.parameters[4 + 4 * i] = kBroadStartExponent;
  }
  return {retro, broad};
}

ChannelFit FitTexelChannel(const TexelSamples& samples, int channel, const TexelFitOptions& options,
                           std::span<const ChannelStart> starts) {
  ChannelFit fit = FitChannel(samples.geometry(), samples.Channel(channel), options, starts);
  fit.squared_error += samples.PooledSpread(channel);
  fit.samples = samples.raw_count();
  fit.weight = samples.raw_weight();
  fit.radiance_sum = samples.RadianceSum(channel);
  return fit;
}

TexelFit CombineChannelFits(const std::array<ChannelFit, 3>& channels, uint32_t lobes) {
  TexelFit fit;
  fit.status = TexelFitStatus::kBlack;  // the least; each channel can only raise it
  fit.brdf.lobe_count = lobes;
  fit.samples = channels[0].samples;
  fit.weight = channels[0].weight;
  fit.lut.assign(channels[0].lut.size(), glm::vec3(1.0f));
  double squared_error = 0.0, radiance_sum = 0.0;
  for (int c = 0; c < 3; ++c) {
    const ChannelFit& channel = channels[c];
    fit.brdf.UnpackChannel(c, channel.parameters.data());
    for (size_t v = 0; v < fit.lut.size(); ++v) fit.lut[v][c] = static_cast<float>(channel.lut[v]);
    squared_error += channel.squared_error;
    radiance_sum += channel.radiance_sum;
    fit.lm_iterations += channel.lm_iterations;
    fit.alternations = std::max(fit.alternations, channel.alternations);
    fit.status = std::max(fit.status, channel.status);
    fit.lut_changes[c] = channel.lut_changes;
  }
  if (fit.weight > 0.0) {
    fit.rmse = std::sqrt(squared_error / (3.0 * fit.weight));
    fit.mean_radiance = radiance_sum / (3.0 * fit.weight);
  }
  return fit;
}

TexelFit FitTexel(const TexelSamples& samples, const TexelFitOptions& options) {
  std::array<ChannelFit, 3> channels;
  for (int c = 0; c < 3; ++c) channels[c] = FitTexelChannel(samples, c, options);
  return CombineChannelFits(channels, options.lobes);
}

}  // namespace loom
