#include "core/fit/texel_fit.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

#include "core/acquire/hemisphere_directions.h"
#include "tests/core/fit/fit_test_data.h"

namespace loom {
namespace {

using testing::CompareRenders;
using testing::MakeTexelSamples;
using testing::SyntheticTexel;

constexpr uint32_t kDirections = 64;  // 8×8 views and 8×8 lights

// Converged to the last digit: tiny threshold, generous caps.
TexelFitOptions TightOptions(uint32_t lobes) {
  TexelFitOptions options;
  options.lobes = lobes;
  options.lut_change_threshold = 1e-9;
  options.max_alternations = 100;
  options.max_lm_iterations = 200;
  return options;
}

LafortuneBrdf OneLobe() {
  LafortuneBrdf brdf;
  brdf.lobe_count = 1;
  brdf.rho = glm::vec3(0.20f, 0.15f, 0.10f);
  brdf.lobes[0] = {glm::vec3(-1.00f, -0.95f, -0.90f), glm::vec3(-1.00f, -0.95f, -0.90f),
                   glm::vec3(0.95f, 0.90f, 0.85f), glm::vec3(12.0f, 10.0f, 8.0f)};
  return brdf;
}

// Two anisotropic lobes, lobe 1 elongated along x as the fit's start is.
LafortuneBrdf TwoLobes() {
  LafortuneBrdf brdf;
  brdf.lobe_count = 2;
  brdf.rho = glm::vec3(0.12f, 0.18f, 0.08f);
  brdf.lobes[0] = {glm::vec3(-1.00f, -0.98f, -0.96f), glm::vec3(-0.80f, -0.85f, -0.75f),
                   glm::vec3(0.90f, 0.95f, 0.85f), glm::vec3(15.0f, 12.0f, 18.0f)};
  brdf.lobes[1] = {glm::vec3(-0.70f, -0.65f, -0.75f), glm::vec3(-0.95f, -0.93f, -0.97f),
                   glm::vec3(0.80f, 0.85f, 0.75f), glm::vec3(6.0f, 5.0f, 7.0f)};
  return brdf;
}

// A lookup table that darkens and reddens towards grazing views, as yarn occlusion does.
std::vector<glm::vec3> ColouredLut() {
  std::vector<glm::vec3> lut;
  for (const glm::vec3& v : HemisphereGridDirections(kDirections)) {
    lut.emplace_back(0.9f + 0.3f * (1.0f - v.z), 1.1f - 0.5f * (1.0f - v.z), 1.0f - 0.4f * (1.0f - v.z) + 0.1f * v.x);
  }
  return lut;
}

double Relative(double fitted, double truth) { return std::abs(fitted - truth) / std::abs(truth); }

// T · f_1 is invariant under T → s·T, ρ → ρ/s, C_i → C_i·s^{−1/N_i} per channel, so
// parameters are compared after moving the fit to the truth's scale (taken from
// the first view's T; 1 without a table).
void ExpectParametersRecovered(const SyntheticTexel& truth, const TexelFit& fit, double tolerance) {
  ASSERT_EQ(fit.brdf.lobe_count, truth.brdf.lobe_count);
  for (int c = 0; c < 3; ++c) {
    const double s = truth.lut.empty() ? 1.0 : double{fit.lut[0][c]} / truth.lut[0][c];
    EXPECT_LT(Relative(fit.brdf.rho[c] * s, truth.brdf.rho[c]), tolerance) << "rho channel " << c;
    for (uint32_t i = 0; i < truth.brdf.lobe_count; ++i) {
      const LafortuneLobe& f = fit.brdf.lobes[i];
      const LafortuneLobe& t = truth.brdf.lobes[i];
      EXPECT_LT(Relative(f.n[c], t.n[c]), tolerance) << "N lobe " << i << " channel " << c;
      const double lobe_scale = std::pow(s, 1.0 / f.n[c]);
      EXPECT_LT(Relative(f.cx[c] * lobe_scale, t.cx[c]), tolerance) << "Cx lobe " << i << " channel " << c;
      EXPECT_LT(Relative(f.cy[c] * lobe_scale, t.cy[c]), tolerance) << "Cy lobe " << i << " channel " << c;
      EXPECT_LT(Relative(f.cz[c] * lobe_scale, t.cz[c]), tolerance) << "Cz lobe " << i << " channel " << c;
    }
    if (!truth.lut.empty()) {
      for (size_t v = 0; v < truth.lut.size(); ++v) {
        EXPECT_LT(Relative(fit.lut[v][c] / s, truth.lut[v][c]), tolerance) << "T view " << v << " channel " << c;
      }
    }
  }
}

void ExpectFinite(const TexelFit& fit) {
  EXPECT_TRUE(fit.brdf.AllFinite());
  for (const glm::vec3& t : fit.lut) EXPECT_TRUE(std::isfinite(t.x) && std::isfinite(t.y) && std::isfinite(t.z));
  EXPECT_TRUE(std::isfinite(fit.rmse));
}

TexelFit FitAndCheck(const SyntheticTexel& truth, const TexelFitOptions& options) {
  const TexelFit fit = FitTexel(MakeTexelSamples(truth, kDirections, kDirections), options);
  ExpectFinite(fit);
  return fit;
}

TEST(TexelFit, RecoversOneLobe) {
  const SyntheticTexel truth(OneLobe());
  const TexelFit fit = FitAndCheck(truth, TightOptions(1));
  EXPECT_EQ(fit.status, TexelFitStatus::kOk);
  ExpectParametersRecovered(truth, fit, 1e-3);
  const auto error = CompareRenders(truth, fit, kDirections, kDirections);
  EXPECT_LT(error.rmse, 1e-4 * error.mean);
}

TEST(TexelFit, RecoversTwoAnisotropicLobes) {
  const SyntheticTexel truth(TwoLobes());
  const TexelFit fit = FitAndCheck(truth, TightOptions(2));
  EXPECT_EQ(fit.status, TexelFitStatus::kOk);
  ExpectParametersRecovered(truth, fit, 1e-3);
  const auto error = CompareRenders(truth, fit, kDirections, kDirections);
  EXPECT_LT(error.rmse, 1e-4 * error.mean);
}

TEST(TexelFit, RecoversColouredLookupTable) {
  const SyntheticTexel truth(TwoLobes(), ColouredLut());
  const TexelFit fit = FitAndCheck(truth, TightOptions(2));
  EXPECT_EQ(fit.status, TexelFitStatus::kOk);
  ExpectParametersRecovered(truth, fit, 1e-3);
  const auto error = CompareRenders(truth, fit, kDirections, kDirections);
  EXPECT_LT(error.rmse, 1e-4 * error.mean);
}

// The texels above with a brighter diffuse part, as cloth has: with 2% noise on
// every sample, each view's T is estimated from 64 samples of which the few in the
// highlight dominate, so the table's own noise is what bounds the render error.
LafortuneBrdf Brighter(LafortuneBrdf brdf) {
  brdf.rho *= 2.0f;
  return brdf;
}

// The alternation converges linearly (each round removes about a fifth of the LUT
// error on these texels), so the paper's threshold of 0.1 stops after one or two
// rounds with the table a few per cent off; render equivalence needs a tighter one.
TEST(TexelFit, NoisySamplesAreRenderEquivalent) {
  TexelFitOptions options = MakeTexelFitOptions({});
  options.lut_change_threshold = 1e-3;
  options.max_alternations = 100;
  for (const SyntheticTexel& truth : {SyntheticTexel(Brighter(OneLobe()), {}, 0.02, 7),
                                      SyntheticTexel(Brighter(TwoLobes()), {}, 0.02, 8),
                                      SyntheticTexel(Brighter(TwoLobes()), ColouredLut(), 0.02, 9)}) {
    const TexelFit fit = FitAndCheck(truth, options);
    EXPECT_NE(fit.status, TexelFitStatus::kDiffuseOnly);
    const auto error = CompareRenders(truth, fit, kDirections, kDirections);
    EXPECT_LT(error.rmse, 0.01 * error.mean) << "lobes " << truth.brdf.lobe_count << ", table " << !truth.lut.empty();
  }
}

TEST(TexelFit, WithoutLookupTableKeepsTOne) {
  TexelFitOptions options = MakeTexelFitOptions({});
  options.lookup_table = false;
  const TexelFit fit = FitAndCheck(SyntheticTexel(TwoLobes(), ColouredLut()), options);
  EXPECT_EQ(fit.alternations, 1u);
  for (const glm::vec3& t : fit.lut) EXPECT_EQ(t, glm::vec3(1.0f));
}

TEST(TexelFit, LutChangeSequenceIsNonIncreasing) {
  const SyntheticTexel truth(TwoLobes(), ColouredLut(), 0.02, 3);
  TexelFitOptions options = MakeTexelFitOptions({});
  options.lut_change_threshold = 1e-4;
  options.max_alternations = 30;
  const TexelFit fit = FitAndCheck(truth, options);
  for (int c = 0; c < 3; ++c) {
    const std::vector<double>& changes = fit.lut_changes[c];
    ASSERT_GE(changes.size(), 2u) << "channel " << c;
    for (size_t i = 1; i < changes.size(); ++i) {
      EXPECT_LE(changes[i], changes[i - 1]) << "channel " << c << " alternation " << i;
    }
    EXPECT_LT(changes.back(), options.lut_change_threshold) << "converged, channel " << c;
  }
}

// A mip texel's samples of one view and light share their directions; pooled into
// one (coverage-weighted mean radiance, weight Σ coverage) they give the fit, error
// and RMSE of the raw rays: here copy j, of coverage w_j, stands for 4·w_j raw
// samples. Not to the last digit: Ceres stops on the relative decrease of the
// cost, and the raw cost carries the noise's spread between the copies, which the
// pooled cost leaves out, so the raw fit stops a little earlier (a little worse).
TEST(TexelFit, PooledSamplesFitLikeTheRawOnes) {
  constexpr int kCopies = 4;
  constexpr std::array<float, kCopies> kCoverages = {1.0f, 0.5f, 0.25f, 0.25f};
  const SyntheticTexel truth(TwoLobes(), ColouredLut());
  const std::vector<glm::vec3> directions = HemisphereGridDirections(kDirections);
  std::mt19937 random(5);
  std::normal_distribution<float> noise(1.0f, 0.05f);
  TexelSamples raw(kDirections), pooled(kDirections);
  for (uint32_t v = 0; v < kDirections; ++v) {
    for (const glm::vec3& l : directions) {
      std::array<glm::vec3, kCopies> radiances;
      for (int j = 0; j < kCopies; ++j) {
        radiances[j] = testing::RenderModel(truth.brdf, truth.lut, v, l, directions[v]) *
                       glm::vec3(noise(random), noise(random), noise(random));
        for (int n = 0; n < int(4 * kCoverages[j]); ++n) raw.Add(l, directions[v], v, radiances[j]);
      }
      pooled.AddPooled(l, directions[v], v, radiances, kCoverages);
    }
  }
  ASSERT_EQ(pooled.size() * 8, raw.size());
  const TexelFitOptions options = TightOptions(2);
  const TexelFit from_raw = FitTexel(raw, options), from_pooled = FitTexel(pooled, options);
  EXPECT_EQ(from_pooled.samples, pooled.size() * kCopies);
  EXPECT_NEAR(from_pooled.weight * 4, from_raw.weight, 1e-9 * from_raw.weight);
  EXPECT_NEAR(from_pooled.mean_radiance, from_raw.mean_radiance, 1e-12 * from_raw.mean_radiance);
  EXPECT_LE(from_pooled.rmse, from_raw.rmse * (1.0 + 1e-9));
  EXPECT_GT(from_pooled.rmse, from_raw.rmse * (1.0 - 1e-3));
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(from_pooled.brdf.rho[c], from_raw.brdf.rho[c], 1e-3 * from_raw.brdf.rho[c]) << "channel " << c;
  }
}

// The fit runs from the paper's start and from every given one (a mip texel's
// parent's fit) and keeps the least error: among poor candidates and a converged
// fit, the result is no worse than the cold fit, and every start was fitted.
TEST(TexelFit, ExtraStartsKeepTheFitWithTheLeastError) {
  const SyntheticTexel truth(Brighter(TwoLobes()), ColouredLut(), 0.02, 4);
  const TexelSamples samples = MakeTexelSamples(truth, kDirections, kDirections);
  const TexelFitOptions options = MakeTexelFitOptions({});
  for (int c = 0; c < 3; ++c) {
    const ChannelFit cold = FitTexelChannel(samples, c, options);
    ASSERT_EQ(cold.status, TexelFitStatus::kOk);
    ChannelStart far = {cold.parameters, std::vector<double>(kDirections, 1.0)};
    far.parameters[0] *= 5.0;  // much too bright
    const ChannelStart off = {{cold.parameters[0], 0, 0, 0, 1, 0, 0, 0, 1}, cold.lut};  // lobes off
    const std::vector<ChannelStart> starts = {far, off, {cold.parameters, cold.lut}};
    const ChannelFit warm = FitTexelChannel(samples, c, options, starts);
    EXPECT_EQ(warm.status, TexelFitStatus::kOk) << "channel " << c;
    EXPECT_LE(warm.squared_error, cold.squared_error * (1.0 + 1e-9)) << "channel " << c;
    EXPECT_GT(warm.lm_iterations, cold.lm_iterations) << "channel " << c << ": the iterations of every start";
  }
}

// The top level's extra starts: the paper's with its last lobe retro-reflective,
// and with every lobe broad at the same peak.
TEST(TexelFit, AlternativeStartsShareThePapersPeak) {
  const SyntheticTexel truth(TwoLobes(), ColouredLut());
  const TexelSamples samples = MakeTexelSamples(truth, kDirections, kDirections);
  const std::vector<double> paper = StartParameters(samples.geometry(), samples.Channel(1), 2);
  const std::vector<ChannelStart> starts = AlternativeStarts(samples, 1, 2);
  ASSERT_EQ(starts.size(), 2u);
  const double peak = std::pow(paper[3], paper[4]);
  ASSERT_GT(peak, 0.0);
  const std::vector<double>& retro = starts[0].parameters;
  EXPECT_EQ(std::vector<double>(retro.begin(), retro.begin() + 5), std::vector<double>(paper.begin(), paper.begin() + 5));
  EXPECT_EQ(retro[5], paper[3]);
  EXPECT_EQ(retro[6], paper[3]);
  EXPECT_EQ(retro[7], paper[3]);
  const std::vector<double>& broad = starts[1].parameters;
  for (int lobe = 0; lobe < 2; ++lobe) {
    EXPECT_EQ(broad[4 + 4 * lobe], 3.0);
    EXPECT_NEAR(std::pow(broad[3 + 4 * lobe], broad[4 + 4 * lobe]), peak, 1e-12 * peak) << "lobe " << lobe;
  }
  for (const ChannelStart& start : starts) EXPECT_EQ(start.lut, std::vector<double>(kDirections, 1.0));
}

// --- Pathological texels ---------------------------------------------------------------

TEST(TexelFit, AllZeroRadianceIsBlack) {
  LafortuneBrdf black;
  black.lobe_count = 2;
  const TexelFit fit = FitAndCheck(SyntheticTexel(black), MakeTexelFitOptions({}));
  EXPECT_EQ(fit.status, TexelFitStatus::kBlack);
  EXPECT_EQ(fit.rmse, 0.0);
  EXPECT_EQ(fit.brdf.Evaluate(glm::vec3(0, 0, 1), glm::vec3(0, 0, 1)), glm::vec3(0.0f));
}

TEST(TexelFit, HoleForEveryViewIsEmpty) {
  SyntheticTexel hole(TwoLobes());
  hole.visible = [](uint32_t, glm::vec3) { return false; };
  const TexelFit fit = FitAndCheck(hole, MakeTexelFitOptions({}));
  EXPECT_EQ(fit.status, TexelFitStatus::kEmpty);
  EXPECT_EQ(fit.lm_iterations, 0u);
}

TEST(TexelFit, SingleValidViewFitsThatView) {
  SyntheticTexel truth(TwoLobes(), ColouredLut());
  truth.visible = [](uint32_t view, glm::vec3) { return view == 27; };
  const TexelFit fit = FitAndCheck(truth, MakeTexelFitOptions({}));
  EXPECT_LE(fit.status, TexelFitStatus::kFewerLobes);
  const auto error = CompareRenders(truth, fit, kDirections, kDirections);
  EXPECT_LT(error.rmse, 0.01 * error.mean);
}

TEST(TexelFit, GrazingOnlyViews) {
  SyntheticTexel truth(TwoLobes(), ColouredLut());
  truth.visible = [](uint32_t, glm::vec3 v) { return v.z < 0.3f; };
  const TexelFit fit = FitAndCheck(truth, MakeTexelFitOptions({}));
  EXPECT_LE(fit.status, TexelFitStatus::kFewerLobes);
  const auto error = CompareRenders(truth, fit, kDirections, kDirections);
  EXPECT_LT(error.rmse, 0.01 * error.mean);
}

TEST(TexelFit, ExtremeShininessStaysFinite) {
  LafortuneBrdf mirror;
  mirror.lobe_count = 1;
  mirror.rho = glm::vec3(0.05f);
  mirror.lobes[0] = {glm::vec3(-1.0f), glm::vec3(-1.0f), glm::vec3(1.0f), glm::vec3(250.0f)};
  const TexelFit fit = FitAndCheck(SyntheticTexel(mirror), MakeTexelFitOptions({}));
  EXPECT_LE(fit.status, TexelFitStatus::kFewerLobes);
}

// Lambertian under a strongly view-dependent table: the closed-form diffuse fit
// (with its T) is exact, while the lobe fits stop at the default threshold a little
// short of it (the first lobe fit, with T = 1, bends the lobes to mimic the table),
// so the texel falls back through fewer lobes to diffuse only, and renders exactly.
TEST(TexelFit, DiffuseUnderATableFallsBackToTheExactDiffuseFit) {
  LafortuneBrdf matte;
  matte.lobe_count = 2;
  matte.rho = glm::vec3(0.3f, 0.2f, 0.1f);
  const SyntheticTexel truth(matte, ColouredLut());
  const TexelFit fit = FitAndCheck(truth, MakeTexelFitOptions({}));
  EXPECT_EQ(fit.status, TexelFitStatus::kDiffuseOnly) << TexelFitStatusName(fit.status);
  const auto error = CompareRenders(truth, fit, kDirections, kDirections);
  EXPECT_LT(error.rmse, 1e-3 * error.mean);
}

}  // namespace
}  // namespace loom
