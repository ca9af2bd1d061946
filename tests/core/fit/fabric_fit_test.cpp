#include "core/fit/fabric_fit.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "core/acquire/hemisphere_directions.h"
#include "core/util/error.h"

namespace loom {
namespace {

constexpr uint32_t kResolution = 4;
constexpr uint32_t kDirections = 64;
constexpr size_t kEmptyTexel = 5;      // a hole from every view
constexpr size_t kHalfHoleTexel = 10;  // a hole from the views with y < 0

LafortuneBrdf Glossy(float tint) {
  LafortuneBrdf brdf;
  brdf.lobe_count = 2;
  brdf.rho = glm::vec3(0.15f, 0.12f * tint, 0.08f);
  brdf.lobes[0] = {glm::vec3(-1.0f), glm::vec3(-0.8f), glm::vec3(0.9f), glm::vec3(12.0f)};
  brdf.lobes[1] = {glm::vec3(-0.7f), glm::vec3(-0.95f), glm::vec3(0.8f), glm::vec3(6.0f)};
  return brdf;
}

LafortuneBrdf Matte() {
  LafortuneBrdf brdf;
  brdf.lobe_count = 2;
  brdf.rho = glm::vec3(0.3f, 0.25f, 0.2f);
  brdf.lobes[0] = {glm::vec3(0.6f), glm::vec3(0.6f), glm::vec3(0.6f), glm::vec3(2.0f)};  // retro-reflective sheen
  return brdf;
}

// A checkerboard of two known BRDFs on tilted normals.
LafortuneBrdf TrueBrdf(size_t texel) {
  const size_t x = texel % kResolution, y = texel / kResolution;
  return (x + y) % 2 == 0 ? Glossy(1.0f + 0.1f * float(x)) : Matte();
}

glm::vec3 TrueNormal(size_t texel) {
  const size_t x = texel % kResolution, y = texel / kResolution;
  return glm::normalize(glm::vec3(0.1f * (float(x) - 1.5f), -0.08f * (float(y) - 1.5f), 1.0f));
}

// The checkerboard rendered exactly as the model (so level 0 can be fitted
// exactly), with one empty texel and one that half the views cannot see.
RadianceSamples MakeFabricSamples() {
  RadianceSamples samples(kResolution, HemisphereGridDirections(kDirections), HemisphereGridDirections(kDirections));
  for (size_t texel = 0; texel < samples.texel_count(); ++texel) {
    const glm::vec3 normal = TrueNormal(texel);
    samples.normals[texel] = normal;
    samples.tangents[texel] = TexelTangent(normal);
    const TexelFrame frame(normal, samples.tangents[texel]);
    const LafortuneBrdf brdf = TrueBrdf(texel);
    for (size_t v = 0; v < samples.view_count(); ++v) {
      const glm::vec3 view = samples.view_directions[v];
      const bool visible = texel != kEmptyTexel && !(texel == kHalfHoleTexel && view.y < 0.0f);
      samples.alpha[samples.AlphaIndex(texel, v)] = visible ? 1.0f : 0.0f;
      if (!visible) continue;
      for (size_t l = 0; l < samples.light_count(); ++l) {
        samples.radiance[samples.RadianceIndex(texel, v, l)] =
            brdf.Evaluate(frame.ToLocal(samples.light_directions[l]), frame.ToLocal(view));
      }
    }
  }
  return samples;
}

bool Finite(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

class FabricFitTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    samples_ = new RadianceSamples(MakeFabricSamples());
    fabric_ = new FittedFabric(FitFabric(*samples_, {}, {}, 2));
  }
  static void TearDownTestSuite() {
    delete fabric_;
    delete samples_;
  }
  static RadianceSamples* samples_;
  static FittedFabric* fabric_;
};
RadianceSamples* FabricFitTest::samples_ = nullptr;
FittedFabric* FabricFitTest::fabric_ = nullptr;

TEST_F(FabricFitTest, FitsEveryLevelWithFiniteValues) {
  const FittedFabric& fabric = *fabric_;
  ASSERT_EQ(fabric.levels.size(), 3u);  // 4×4, 2×2, 1×1
  EXPECT_EQ(fabric.lobes, 2u);
  for (uint32_t k = 0; k < fabric.levels.size(); ++k) {
    const FittedLevel& level = fabric.levels[k];
    const size_t texels = size_t{level.resolution} * level.resolution;
    EXPECT_EQ(level.resolution, kResolution >> k);
    ASSERT_EQ(level.brdfs.size(), texels);
    ASSERT_EQ(level.lut.size(), texels * kDirections);
    ASSERT_EQ(level.alpha.size(), texels * kDirections);
    for (const LafortuneBrdf& brdf : level.brdfs) EXPECT_TRUE(brdf.AllFinite());
    for (const glm::vec3& t : level.lut) EXPECT_TRUE(Finite(t));
    for (float r : level.rmse) EXPECT_TRUE(std::isfinite(r));
    EXPECT_EQ(level.stats.level, k);
    EXPECT_EQ(level.stats.fewer_lobes + level.stats.diffuse_only, 0u) << "level " << k;
  }
}

// A coarse texel's samples are its children's, which differ from each other, so
// its residual holds their spread: what the fit must match is their mean.
// Relative RMSE of texel `texel` of level k against the mean of the level-0
// texels it covers (where visible), over every view and light.
double ErrorAgainstChildrenMean(const FittedFabric& fabric, const RadianceSamples& samples, uint32_t k,
                                size_t texel) {
  const FittedLevel& level = fabric.levels[k];
  const TexelFrame frame(level.normals[texel], level.tangents[texel]);
  const size_t span = size_t{1} << k;
  const size_t x0 = (texel % level.resolution) * span, y0 = (texel / level.resolution) * span;
  double squared = 0.0, sum = 0.0;
  size_t count = 0;
  for (size_t v = 0; v < samples.view_count(); ++v) {
    for (size_t l = 0; l < samples.light_count(); ++l) {
      glm::dvec3 mean(0.0);
      double visible = 0;
      for (size_t y = y0; y < y0 + span; ++y) {
        for (size_t x = x0; x < x0 + span; ++x) {
          const size_t child = y * kResolution + x;
          if (samples.alpha[samples.AlphaIndex(child, v)] == 0.0f) continue;
          mean += glm::dvec3(samples.radiance[samples.RadianceIndex(child, v, l)]);
          ++visible;
        }
      }
      if (visible == 0) continue;
      mean /= visible;
      const glm::vec3 lut = level.lut[texel * samples.view_count() + v];
      const glm::dvec3 model = lut * level.brdfs[texel].Evaluate(frame.ToLocal(samples.light_directions[l]),
                                                                 frame.ToLocal(samples.view_directions[v]));
      squared += glm::dot(model - mean, model - mean);
      sum += mean.x + mean.y + mean.z;
      count += 3;
    }
  }
  return std::sqrt(squared / count) / (sum / count);
}

TEST_F(FabricFitTest, LevelZeroIsExactAndCoarseLevelsMatchTheirChildrensMean) {
  const FitLevelStats& fine = fabric_->levels[0].stats;
  EXPECT_LT(fine.relative_rmse, 1e-3);
  // 15 texels: every visible (view, light) of 14 full texels and half of another.
  EXPECT_EQ(fine.samples, (14 * kDirections + kDirections / 2) * kDirections);
  for (uint32_t k = 0; k < fabric_->levels.size(); ++k) {
    const FittedLevel& level = fabric_->levels[k];
    EXPECT_EQ(level.stats.samples, fine.samples) << "every level pools the same samples";
    EXPECT_LE(level.stats.rmse_mean, level.stats.rmse_p95);
    EXPECT_LE(level.stats.rmse_p95, level.stats.rmse_max);
    EXPECT_GE(level.stats.mean_alternations, 1.0);
    EXPECT_LT(level.stats.mean_alternations, 8.0) << "the alternation converged before its cap";
    for (size_t texel = 0; texel < level.brdfs.size(); ++texel) {
      if (level.status[texel] == TexelFitStatus::kEmpty) continue;
      // Level 0 is exact; a coarse texel pools tilted normals and a retro-reflective
      // lobe a 2-lobe fit has no room for, and stops at the default LUT threshold.
      EXPECT_LT(ErrorAgainstChildrenMean(*fabric_, *samples_, k, texel), k == 0 ? 1e-6 : 0.1)
          << "level " << k << " texel " << texel;
    }
  }
}

TEST_F(FabricFitTest, EmptyTexelIsFlaggedAndTakesItsParent) {
  const FittedLevel& fine = fabric_->levels[0];
  const FittedLevel& parent = fabric_->levels[1];
  EXPECT_EQ(fine.stats.empty, 1u);
  EXPECT_EQ(fine.status[kEmptyTexel], TexelFitStatus::kEmpty);
  EXPECT_EQ(parent.stats.empty, 0u);
  const size_t parent_texel = (kEmptyTexel / kResolution / 2) * parent.resolution + (kEmptyTexel % kResolution) / 2;
  EXPECT_EQ(fine.brdfs[kEmptyTexel].rho, parent.brdfs[parent_texel].rho);
  EXPECT_EQ(fine.lut[kEmptyTexel * kDirections + 7], parent.lut[parent_texel * kDirections + 7]);
  EXPECT_EQ(fine.alpha[kEmptyTexel * kDirections + 7], 0.0f) << "still a hole";
}

TEST_F(FabricFitTest, CoarseGeometryAveragesChildren) {
  const FittedLevel& fine = fabric_->levels[0];
  const FittedLevel& coarse = fabric_->levels[1];
  // Texel (1, 0) of level 1 covers level-0 texels 2, 3, 6, 7; 5 is in (0, 0).
  glm::vec3 normal(0.0f);
  float alpha = 0.0f;
  for (size_t child : {2, 3, 6, 7}) {
    normal += fine.normals[child];
    alpha += fine.alpha[child * kDirections] / 4;
  }
  EXPECT_NEAR(glm::length(glm::normalize(normal) - coarse.normals[1]), 0.0f, 1e-6f);
  EXPECT_NEAR(glm::dot(coarse.tangents[1], coarse.normals[1]), 0.0f, 1e-6f);
  EXPECT_FLOAT_EQ(coarse.alpha[1 * kDirections], alpha);
  EXPECT_FLOAT_EQ(coarse.alpha[0 * kDirections], 0.75f) << "three of four children visible";
}

// A texel's radiance is the mean over its rays that hit yarn, so a coarse texel
// must weight its children by coverage: here one full child of diffuse albedo 0.3
// and one hit by a quarter of its rays, of albedo 0.1 (the other two are holes),
// make a parent of (1 · 0.3 + 0.25 · 0.1) / 1.25 = 0.26, not the children's plain
// mean 0.2. Their normals are averaged with the same weights.
TEST(FabricFit, CoarseTexelsWeightTheirChildrenByCoverage) {
  constexpr uint32_t kDirections16 = 16;
  RadianceSamples samples(2, HemisphereGridDirections(kDirections16), HemisphereGridDirections(kDirections16));
  const std::array<float, 4> albedo = {0.3f, 0.1f, 0.0f, 0.0f}, coverage = {1.0f, 0.25f, 0.0f, 0.0f};
  const std::array<glm::vec3, 4> normals = {glm::normalize(glm::vec3(0.2f, 0.0f, 1.0f)),
                                            glm::normalize(glm::vec3(-0.2f, 0.0f, 1.0f)), glm::vec3(0, 0, 1),
                                            glm::vec3(0, 0, 1)};
  for (size_t texel = 0; texel < 4; ++texel) {
    samples.normals[texel] = normals[texel];
    samples.tangents[texel] = TexelTangent(normals[texel]);
    for (size_t v = 0; v < samples.view_count(); ++v) {
      samples.alpha[samples.AlphaIndex(texel, v)] = coverage[texel];
      for (size_t l = 0; l < samples.light_count(); ++l) {
        // A Lambertian yarn lying flat, per unit irradiance.
        const float cosine = std::max(0.0f, samples.light_directions[l].z);
        samples.radiance[samples.RadianceIndex(texel, v, l)] = glm::vec3(albedo[texel] / float(M_PI) * cosine);
      }
    }
  }
  v1::PrecomputeSettings settings;
  settings.set_lobes(1);
  const FittedFabric fabric = FitFabric(samples, settings, {}, 1);
  ASSERT_EQ(fabric.levels.size(), 2u);
  const FittedLevel& parent = fabric.levels[1];

  const glm::vec3 expected_normal = glm::normalize(1.0f * normals[0] + 0.25f * normals[1]);
  EXPECT_LT(glm::length(parent.normals[0] - expected_normal), 1e-5f);
  EXPECT_FLOAT_EQ(parent.alpha[0], 1.25f / 4.0f);

  // The parent's model summed over every pair, against the same sum of albedo
  // 0.26 (the plain mean's 0.2 would be 23% short).
  const TexelFrame frame(parent.normals[0], parent.tangents[0]);
  double model_sum = 0.0, expected_sum = 0.0;
  for (size_t v = 0; v < samples.view_count(); ++v) {
    for (size_t l = 0; l < samples.light_count(); ++l) {
      const glm::vec3 model = parent.lut[v] * parent.brdfs[0].Evaluate(frame.ToLocal(samples.light_directions[l]),
                                                                      frame.ToLocal(samples.view_directions[v]));
      model_sum += model.x;
      expected_sum += 0.26 / M_PI * std::max(0.0f, samples.light_directions[l].z);
    }
  }
  EXPECT_NEAR(model_sum / expected_sum, 1.0, 0.02);
}

// The samples with each 2×2 block of texels replaced by what level 1 pools from it:
// coverage-weighted radiance, mean coverage, the rays' mean normal. Level 1 and
// above see the same samples as before; level 0 sees four copies of them.
RadianceSamples PooledIntoBlocks(const RadianceSamples& fine) {
  RadianceSamples pooled = fine;
  const uint32_t res = fine.resolution;
  const size_t views = fine.view_count(), lights = fine.light_count();
  for (uint32_t by = 0; by < res; by += 2) {
    for (uint32_t bx = 0; bx < res; bx += 2) {
      const std::array<size_t, 4> block = {by * res + bx, by * res + bx + 1, (by + 1) * res + bx, (by + 1) * res + bx + 1};
      glm::dvec3 normal_sum(0.0);
      for (size_t child : block) {
        double coverage = 0.0;
        for (size_t v = 0; v < views; ++v) coverage += fine.alpha[fine.AlphaIndex(child, v)];
        normal_sum += glm::dvec3(fine.normals[child]) * double{fine.normal_lengths[child]} * coverage;
      }
      const glm::vec3 normal(glm::normalize(normal_sum));
      for (size_t v = 0; v < views; ++v) {
        double weight = 0.0;
        for (size_t child : block) weight += fine.alpha[fine.AlphaIndex(child, v)];
        for (size_t l = 0; l < lights; ++l) {
          glm::dvec3 sum(0.0);
          for (size_t child : block) {
            sum += double{fine.alpha[fine.AlphaIndex(child, v)]} * glm::dvec3(fine.radiance[fine.RadianceIndex(child, v, l)]);
          }
          for (size_t child : block) pooled.radiance[pooled.RadianceIndex(child, v, l)] = glm::vec3(weight > 0 ? sum / weight : sum);
        }
        for (size_t child : block) pooled.alpha[pooled.AlphaIndex(child, v)] = static_cast<float>(weight / 4);
      }
      for (size_t child : block) {
        pooled.normals[child] = normal;
        pooled.tangents[child] = TexelTangent(normal);
        pooled.normal_lengths[child] = 1.0f;
      }
    }
  }
  return pooled;
}

// Levels are fitted coarsest first, each from its parent's fit or the paper's start
// (fabric_fit.h), so what level 0 holds cannot change the coarser levels: here
// level 0 is a checkerboard of two BRDFs in one fit and their pooled mean in the
// other, and levels 1 and 2 come out the same, to the iteration. (Fitted finest
// first from the children's fits, as in asset format 4, they differed in both.)
TEST(FabricFit, ACoarseLevelDoesNotDependOnTheFinerLevels) {
  const RadianceSamples checkerboard = MakeFabricSamples();
  const FittedFabric fine = FitFabric(checkerboard, {}, {}, 2);
  const FittedFabric pooled = FitFabric(PooledIntoBlocks(checkerboard), {}, {}, 2);
  ASSERT_EQ(fine.levels.size(), 3u);
  EXPECT_GT(std::abs(fine.levels[0].stats.rmse_mean - pooled.levels[0].stats.rmse_mean), 1e-3)
      << "level 0 fits different samples";
  for (uint32_t k = 1; k < 3; ++k) {
    const FittedLevel& a = fine.levels[k];
    const FittedLevel& b = pooled.levels[k];
    EXPECT_EQ(a.stats.lm_iterations_per_texel, b.stats.lm_iterations_per_texel) << "level " << k;
    for (size_t texel = 0; texel < a.brdfs.size(); ++texel) {
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(a.brdfs[texel].rho[c], b.brdfs[texel].rho[c], 1e-4) << "level " << k << " texel " << texel;
        for (uint32_t j = 0; j < a.brdfs[texel].lobe_count; ++j) {
          EXPECT_NEAR(a.brdfs[texel].lobes[j].n[c], b.brdfs[texel].lobes[j].n[c], 1e-3 * a.brdfs[texel].lobes[j].n[c])
              << "level " << k << " texel " << texel << " lobe " << j;
        }
      }
    }
  }
}

TEST(FabricFit, ResultDoesNotDependOnThreadCount) {
  const RadianceSamples samples = MakeFabricSamples();
  v1::PrecomputeSettings settings;
  settings.set_mip_levels(v1::MIP_LEVELS_NONE);
  settings.set_lobes(1);
  const FittedFabric one = FitFabric(samples, settings, {}, 1);
  const FittedFabric two = FitFabric(samples, settings, {}, 2);
  ASSERT_EQ(one.levels.size(), 1u);
  for (size_t texel = 0; texel < one.levels[0].brdfs.size(); ++texel) {
    EXPECT_EQ(one.levels[0].brdfs[texel].rho, two.levels[0].brdfs[texel].rho);
    EXPECT_EQ(one.levels[0].brdfs[texel].lobes[0].n, two.levels[0].brdfs[texel].lobes[0].n);
  }
  EXPECT_EQ(one.levels[0].lut, two.levels[0].lut);
}

TEST(FabricFit, WithoutMipLevelsAnEmptyTexelTakesItsNearestNeighbour) {
  const RadianceSamples samples = MakeFabricSamples();
  v1::PrecomputeSettings settings;
  settings.set_mip_levels(v1::MIP_LEVELS_NONE);
  settings.set_lookup_table(false);
  std::vector<double> fractions;
  const FittedFabric fabric = FitFabric(samples, settings, [&](double f, std::string_view) { fractions.push_back(f); });
  const FittedLevel& level = fabric.levels[0];
  EXPECT_EQ(level.status[kEmptyTexel], TexelFitStatus::kEmpty);
  EXPECT_EQ(level.brdfs[kEmptyTexel].rho, level.brdfs[kEmptyTexel - 1].rho) << "texel 4, the first at distance 1";
  ASSERT_FALSE(fractions.empty());
  EXPECT_TRUE(std::is_sorted(fractions.begin(), fractions.end()));
  EXPECT_EQ(fractions.back(), 1.0);
}

TEST(FabricFit, MipLevelsNeedAPowerOfTwo) {
  const RadianceSamples samples(3, HemisphereGridDirections(4), HemisphereGridDirections(4));
  EXPECT_THROW(FitFabric(samples, {}), Error);
}

}  // namespace
}  // namespace loom
