// The factored method: the factorisation, its asset, its settings and key, and its
// GLSL against the C++ evaluation per pixel.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "core/acquire/hemisphere_directions.h"
#include "core/methods/factored/factored_method.h"
#include "core/spec/defaults.h"
#include "core/spec/fabric_key.h"
#include "core/spec/validate.h"
#include "tests/core/methods/method_test_data.h"
#include "tests/core/methods/plane_probe.h"

namespace loom {
namespace {

// A table every texel of which is separable per channel, A(v)·B(l): rank 1 holds it.
RadianceSamples SeparableSamples(uint32_t resolution, uint32_t views, uint32_t lights) {
  RadianceSamples samples(resolution, HemisphereGridDirections(views), HemisphereGridDirections(lights));
  for (size_t texel = 0; texel < samples.texel_count(); ++texel) {
    const glm::vec3 tint(0.2f + 0.1f * static_cast<float>(texel % 3), 0.4f, 0.6f - 0.1f * static_cast<float>(texel % 4));
    for (size_t view = 0; view < samples.view_count(); ++view) {
      samples.alpha[samples.AlphaIndex(texel, view)] = 1.0f;
      const float a = 0.5f + samples.view_directions[view].z + 0.3f * samples.view_directions[view].x;
      for (size_t light = 0; light < samples.light_count(); ++light) {
        const glm::vec3 l = samples.light_directions[light];
        samples.radiance[samples.RadianceIndex(texel, view, light)] = tint * a * l.z * (1.2f + l.y);
      }
    }
  }
  return samples;
}

TEST(FactoredFabric, RankOneRecoversASeparableTable) {
  const RadianceSamples samples = SeparableSamples(4, 16, 16);
  const TabulatedFabric table = TabulateFabric(samples, true);
  const FactoredFabric fabric = FactorFabric(table, 1, 2);
  for (const FactoredLevel& level : fabric.levels) EXPECT_LT(level.relative_rmse, 1e-5);
  for (size_t texel = 0; texel < samples.texel_count(); texel += 3) {
    for (size_t view = 0; view < samples.view_count(); ++view) {
      for (size_t light = 0; light < samples.light_count(); ++light) {
        const glm::vec4 value =
            EvaluateFactored(fabric, 0, texel, samples.view_directions[view], samples.light_directions[light]);
        const glm::vec3 expected = samples.radiance[samples.RadianceIndex(texel, view, light)];
        for (int c = 0; c < 3; ++c) ASSERT_NEAR(value[c], expected[c], 1e-4f * (1.0f + expected[c]));
      }
    }
  }
}

// With as many terms as the table's smaller side the factorisation holds any table
// whose colour changes with the view alone (here each texel's tint, and at coarser
// levels the mix of tints its children show from each view, holes included).
TEST(FactoredFabric, FullRankHoldsATableWhoseColourChangesWithTheViewAlone) {
  const RadianceSamples samples = SyntheticSamples(2, 4, 4, true);
  const TabulatedFabric table = TabulateFabric(samples, true);
  const FactoredFabric fabric = FactorFabric(table, 4, 1);
  for (const FactoredLevel& level : fabric.levels) EXPECT_LT(level.relative_rmse, 1e-5);
  for (size_t texel = 0; texel < samples.texel_count(); ++texel) {
    for (size_t view = 0; view < samples.view_count(); ++view) {
      for (size_t light = 0; light < samples.light_count(); ++light) {
        const glm::vec4 factored =
            EvaluateFactored(fabric, 0, texel, samples.view_directions[view], samples.light_directions[light]);
        const glm::vec4 tabulated =
            EvaluateTabulated(table, 0, texel, samples.view_directions[view], samples.light_directions[light]);
        for (int c = 0; c < 4; ++c) ASSERT_NEAR(factored[c], tabulated[c], 1e-5f);
      }
    }
  }
}

// Where the colour changes with the light (two yarns of two colours, each lit from
// its own side) the shared shape cannot follow it, whatever the rank: the limit
// docs/methods/factored.md states.
TEST(FactoredFabric, ColourThatChangesWithTheLightIsBeyondIt) {
  RadianceSamples samples(1, HemisphereGridDirections(16), HemisphereGridDirections(16));
  for (size_t view = 0; view < samples.view_count(); ++view) {
    samples.alpha[samples.AlphaIndex(0, view)] = 1.0f;
    for (size_t light = 0; light < samples.light_count(); ++light) {
      const glm::vec3 l = samples.light_directions[light];
      samples.radiance[samples.RadianceIndex(0, view, light)] =
          l.z * (glm::vec3(0.8f, 0.1f, 0.1f) * std::max(l.x, 0.0f) + glm::vec3(0.1f, 0.1f, 0.8f) * std::max(-l.x, 0.0f));
    }
  }
  const FactoredFabric fabric = FactorFabric(TabulateFabric(samples, false), 8, 1);
  EXPECT_GT(fabric.levels[0].relative_rmse, 0.3);
}

TEST(FactoredFabric, TheErrorFallsWithEveryTermAndIsTheSameOnOneThreadAsOnTwo) {
  const TabulatedFabric table = TabulateFabric(SyntheticSamples(4, 16, 16, true), true);
  double previous = 1e9;
  for (uint32_t rank = 1; rank <= 4; ++rank) {
    const double error = FactorFabric(table, rank, 2).levels[0].relative_rmse;
    EXPECT_LT(error, previous) << "rank " << rank;
    previous = error;
  }
  const FactoredFabric one = FactorFabric(table, 3, 1), two = FactorFabric(table, 3, 2);
  EXPECT_EQ(one.levels[1].view_terms, two.levels[1].view_terms);
  EXPECT_EQ(one.levels[1].light_terms, two.levels[1].light_terms);
}

TEST(FactoredAsset, RoundTripsInFullFloatsAndRendersAsItsCppEvaluation) {
  const FactoredAsset asset(FactorFabric(TabulateFabric(WithViewHeights(SyntheticSamples(4, 64, 64, true), 0.05f), true), 3));
  const auto directory = std::filesystem::temp_directory_path() / "loom-factored-round-trip";
  std::filesystem::remove_all(directory);
  v1::PrecomputeSettings settings;
  settings.set_method(v1::FABRIC_METHOD_FACTORED);
  settings.set_half_float(false);
  asset.Write(settings, "key", directory);
  const std::unique_ptr<FabricAsset> read = ReadAnyFabricAsset(directory);
  std::filesystem::remove_all(directory);
  ASSERT_EQ(&read->method(), &FactoredMethod());
  const FactoredFabric& a = asset.fabric();
  const FactoredFabric& b = static_cast<const FactoredAsset&>(*read).fabric();
  ASSERT_EQ(b.rank, 3u);
  ASSERT_EQ(b.levels.size(), a.levels.size());
  for (size_t j = 0; j < a.levels.size(); ++j) {
    EXPECT_EQ(b.levels[j].view_terms, a.levels[j].view_terms);
    EXPECT_EQ(b.levels[j].light_terms, a.levels[j].light_terms);
    EXPECT_EQ(b.levels[j].alpha, a.levels[j].alpha);
    EXPECT_EQ(b.levels[j].relative_rmse, a.levels[j].relative_rmse);
  }
  const PlaneProbe probe = ProbePlane(*read, 4, b.view_heights, [&](size_t texel, glm::vec3 view, glm::vec3 light) {
    return EvaluateFactored(b, 0, texel, view, light);
  });
  EXPECT_GT(probe.compared, 96 * 64 / 5);
  EXPECT_LT(probe.worst, 1e-3) << "over " << probe.compared << " pixels";
  std::printf("compared %d pixels, worst relative error %.5f%%\n", probe.compared, 100.0 * probe.worst);
}

TEST(FactoredSettings, TheRankDefaultsToFourIsBoundedAndKeyed) {
  v1::PrecomputeSettings settings;
  settings.set_method(v1::FABRIC_METHOD_FACTORED);
  EXPECT_EQ(WithDefaults(settings).factored().rank(), 4u);
  // The table methods' view grid is 9×9 (a view at the zenith), svbrdf's 8×8.
  EXPECT_EQ(WithDefaults(settings).view_directions(), 81u);
  EXPECT_EQ(WithDefaults(v1::PrecomputeSettings()).view_directions(), 64u);
  settings.mutable_factored()->set_rank(9);
  const ValidationIssues issues = Validate(WithDefaults(settings), "precompute");
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].ToString(), "precompute.factored.rank: 9 exceeds 8");

  v1::FabricSpec fabric;
  fabric.mutable_knit();
  v1::PrecomputeSettings four, two;
  four.set_method(v1::FABRIC_METHOD_FACTORED);
  two = four;
  two.mutable_factored()->set_rank(2);
  EXPECT_NE(FabricKey(fabric, four), FabricKey(fabric, two));
  v1::PrecomputeSettings explicit_four = four;
  explicit_four.mutable_factored()->set_rank(4);
  explicit_four.set_lobes(3);  // svbrdf's fit: not the factored asset's
  EXPECT_EQ(FabricKey(fabric, four), FabricKey(fabric, explicit_four));
  // The other methods ignore the factored settings.
  v1::PrecomputeSettings svbrdf, svbrdf_with_rank;
  svbrdf_with_rank.mutable_factored()->set_rank(2);
  EXPECT_EQ(FabricKey(fabric, svbrdf), FabricKey(fabric, svbrdf_with_rank));
}

}  // namespace
}  // namespace loom
