// The neural method: the training, its asset, its settings and key, and its GLSL
// against the C++ evaluation per pixel.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>

#include "core/acquire/hemisphere_directions.h"
#include "core/methods/neural/neural_method.h"
#include "core/spec/defaults.h"
#include "core/spec/fabric_key.h"
#include "core/spec/validate.h"
#include "core/util/error.h"
#include "core/util/file_io.h"
#include "tests/core/methods/method_test_data.h"
#include "tests/core/methods/plane_probe.h"

namespace loom {
namespace {

NeuralTraining Training(uint32_t steps, uint32_t hidden = 16) { return {8, hidden, 1, steps, 7}; }

// 4×4 texels, each of one of four tints times shape(view, light) (indices of the
// stored directions), every view covered.
TabulatedFabric TintedTable(uint32_t views, uint32_t lights, const std::function<float(size_t, size_t)>& shape) {
  RadianceSamples samples(4, HemisphereGridDirections(views), HemisphereGridDirections(lights));
  for (size_t texel = 0; texel < samples.texel_count(); ++texel) {
    const glm::vec3 tint(0.2f + 0.2f * float(texel % 4), 0.5f, 0.7f - 0.15f * float(texel % 4));
    for (size_t view = 0; view < samples.view_count(); ++view) {
      samples.alpha[samples.AlphaIndex(texel, view)] = 1.0f;
      for (size_t light = 0; light < samples.light_count(); ++light) {
        samples.radiance[samples.RadianceIndex(texel, view, light)] = tint * shape(view, light);
      }
    }
  }
  return TabulateFabric(samples, true);
}

// The trained figures are the evaluation's: EvaluateNeural on a few stored pairs of
// level 1 (pooled) against the table.
void ExpectEvaluationNearTheTable(const NeuralFabric& trained, const TabulatedFabric& table) {
  const size_t views = table.view_count(), lights = table.light_count();
  for (size_t texel = 0; texel < 4; ++texel) {
    for (size_t view = 0; view < views; view += 5) {
      for (size_t light = 0; light < lights; light += 7) {
        const glm::vec4 value =
            EvaluateNeural(trained, 1, texel, table.view_directions[view], table.light_directions[light]);
        const glm::vec3 expected = table.levels[1].radiance[(texel * views + view) * lights + light];
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(value[c], expected[c], 0.03f + 0.05f * expected[c]);
      }
    }
  }
}

// A diffuse table whose colour differs per texel (one of four tints): a latent per
// texel and a small decoder hold it, so training drives the error towards zero
// at every level, each fitted to its own pooled table.
TEST(NeuralFabric, TrainingRecoversATableTheDecoderCanHoldAtEveryLevel) {
  const std::vector<glm::vec3> lights = HemisphereGridDirections(16);
  const TabulatedFabric table = TintedTable(16, 16, [&](size_t, size_t light) { return lights[light].z; });
  const NeuralFabric trained = TrainNeural(table, Training(10000), 2);
  const NeuralFabric barely = TrainNeural(table, Training(20), 2);
  ASSERT_EQ(trained.levels.size(), 3u);
  for (size_t j = 0; j < trained.levels.size(); ++j) {
    std::printf("level %zu: relative RMSE %.3f%% after 10000 steps, %.1f%% after 20\n", j,
                100.0 * trained.levels[j].relative_rmse, 100.0 * barely.levels[j].relative_rmse);
    EXPECT_LT(trained.levels[j].relative_rmse, 0.015) << "level " << j;
    EXPECT_GT(barely.levels[j].relative_rmse, 0.1) << "level " << j;
  }
  ExpectEvaluationNearTheTable(trained, table);
}

// A table whose shape is two separable terms — a lit term and shadows on a scattered
// set of lights, deeper from some views — in four tints: a factored base of two
// terms holds it, and the decoder over it has next to nothing left to learn, where
// the decoder alone, trained as long, cannot follow the scattered shadows.
TEST(NeuralFabric, AFactoredBaseHoldsWhatItsTermsCanAndTheDecoderFitsWhatTheyLeave) {
  const std::vector<glm::vec3> views = HemisphereGridDirections(16), lights = HemisphereGridDirections(64);
  const TabulatedFabric table = TintedTable(16, 64, [&](size_t view, size_t light) {
    const float depth = 0.5f * (views[view].x + 1.0f);
    const float shadowed = (light * 7) % 5 < 2 ? 1.0f : 0.0f;
    return lights[light].z * (1.0f - depth * shadowed);
  });
  NeuralTraining with_base = Training(2000);
  with_base.base_rank = 2;
  const NeuralFabric based = TrainNeural(table, with_base, 2);
  const NeuralFabric alone = TrainNeural(table, Training(2000), 2);
  ASSERT_EQ(based.base.rank, 2u);
  for (size_t j = 0; j < based.levels.size(); ++j) {
    std::printf("level %zu: relative RMSE %.3f%% over the base, %.1f%% alone\n", j,
                100.0 * based.levels[j].relative_rmse, 100.0 * alone.levels[j].relative_rmse);
    EXPECT_LT(based.levels[j].relative_rmse, 0.01) << "level " << j;
    EXPECT_GT(alone.levels[j].relative_rmse, 0.1) << "level " << j;
  }
  ExpectEvaluationNearTheTable(based, table);
}

TEST(NeuralFabric, TrainingIsTheSameOnOneThreadAsOnTwoAndChangesWithTheSeed) {
  const TabulatedFabric table = TabulateFabric(SyntheticSamples(4, 16, 16, true), true);
  const NeuralFabric one = TrainNeural(table, Training(50), 1), two = TrainNeural(table, Training(50), 2);
  EXPECT_EQ(one.decoder.parameters, two.decoder.parameters);
  EXPECT_EQ(one.levels[1].latents, two.levels[1].latents);
  NeuralTraining other = Training(50);
  other.seed = 8;
  EXPECT_NE(TrainNeural(table, other, 2).decoder.parameters, one.decoder.parameters);
}

// With and without a factored base (base_rank 4).
class NeuralAssetWithBase : public testing::TestWithParam<uint32_t> {};

TEST_P(NeuralAssetWithBase, RoundTripsInFullFloatsAndRendersAsItsCppEvaluation) {
  const NeuralAsset asset(TrainNeural(TabulateFabric(WithViewHeights(SyntheticSamples(4, 64, 64, true), 0.05f), true),
                                      {8, 32, 2, 200, 1, GetParam()}));
  const auto directory = std::filesystem::temp_directory_path() / "loom-neural-round-trip";
  std::filesystem::remove_all(directory);
  v1::PrecomputeSettings settings;
  settings.set_method(v1::FABRIC_METHOD_NEURAL);
  settings.set_half_float(false);
  asset.Write(settings, "key", directory);
  const std::unique_ptr<FabricAsset> read = ReadAnyFabricAsset(directory);
  std::filesystem::remove_all(directory);
  ASSERT_EQ(&read->method(), &NeuralMethod());
  const NeuralFabric& a = asset.fabric();
  const NeuralFabric& b = static_cast<const NeuralAsset&>(*read).fabric();
  EXPECT_EQ(b.decoder.parameters, a.decoder.parameters);
  EXPECT_EQ(b.decoder.channels, 8u);
  EXPECT_EQ(b.decoder.hidden, 32u);
  EXPECT_EQ(b.steps, 200u);
  ASSERT_EQ(b.levels.size(), a.levels.size());
  for (size_t j = 0; j < a.levels.size(); ++j) {
    EXPECT_EQ(b.levels[j].latents, a.levels[j].latents);
    EXPECT_EQ(b.levels[j].alpha, a.levels[j].alpha);
    EXPECT_EQ(b.levels[j].relative_rmse, a.levels[j].relative_rmse);
  }
  EXPECT_EQ(b.base.rank, GetParam());
  ASSERT_EQ(b.base.levels.size(), a.base.levels.size());
  for (size_t j = 0; j < a.base.levels.size(); ++j) {
    EXPECT_EQ(b.base.levels[j].view_terms, a.base.levels[j].view_terms);
    EXPECT_EQ(b.base.levels[j].light_terms, a.base.levels[j].light_terms);
  }
  const PlaneProbe probe = ProbePlane(*read, 4, b.view_heights, [&](size_t texel, glm::vec3 view, glm::vec3 light) {
    return EvaluateNeural(b, 0, texel, view, light);
  });
  EXPECT_GT(probe.compared, 96 * 64 / 5);
  EXPECT_LT(probe.worst, 1e-3) << "over " << probe.compared << " pixels";
  std::printf("compared %d pixels, worst relative error %.5f%%\n", probe.compared, 100.0 * probe.worst);
}

INSTANTIATE_TEST_SUITE_P(BaseRank, NeuralAssetWithBase, testing::Values(0u, 4u));

// A manifest edited by hand or corrupted is refused naming the field, before any
// image is read.
TEST(NeuralAsset, ABadDecoderInTheManifestIsRefusedNamingTheField) {
  const NeuralAsset asset(TrainNeural(TabulateFabric(SyntheticSamples(2, 4, 4, false), true), {4, 4, 0, 5, 1}));
  const auto directory = std::filesystem::temp_directory_path() / "loom-neural-bad-manifest";
  const auto refusal = [&](const std::function<void(nlohmann::json&)>& edit) {
    std::filesystem::remove_all(directory);
    asset.Write(v1::PrecomputeSettings(), "key", directory);
    nlohmann::json manifest = nlohmann::json::parse(ReadFile(directory / "manifest.json"));
    edit(manifest);
    WriteFileAtomic(directory / "manifest.json", manifest.dump());
    try {
      ReadAnyFabricAsset(directory);
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument);
      return std::string(e.what());
    }
    return std::string("read");
  };
  EXPECT_THAT(refusal([](nlohmann::json& m) { m["decoder"]["hidden"] = 6; }),
              testing::HasSubstr("decoder.hidden is not a multiple of 4 in [4, 64]"));
  EXPECT_THAT(refusal([](nlohmann::json& m) { m["decoder"]["steps"] = 1e300; }),
              testing::HasSubstr("decoder.steps is not a whole number in [1, 1000000]"));
  EXPECT_THAT(refusal([](nlohmann::json& m) { m["decoder"]["base_rank"] = 9; }),
              testing::HasSubstr("decoder.base_rank is not a whole number in [0, 8]"));
  EXPECT_THAT(refusal([](nlohmann::json& m) { m["decoder"]["parameters"][3] = 1e300; }),
              testing::HasSubstr("decoder.parameters holds a number that is not a finite float"));
  EXPECT_THAT(refusal([](nlohmann::json& m) { m["decoder"]["parameters"].erase(0); }),
              testing::HasSubstr("decoder.parameters must be"));
  EXPECT_EQ(refusal([](nlohmann::json&) {}), "read");  // the unedited asset reads
  std::filesystem::remove_all(directory);
}

TEST(NeuralSettings, DefaultsBoundsAndKey) {
  v1::PrecomputeSettings settings;
  settings.set_method(v1::FABRIC_METHOD_NEURAL);
  const v1::PrecomputeSettings resolved = WithDefaults(settings);
  EXPECT_EQ(resolved.neural().channels(), 8u);
  EXPECT_EQ(resolved.neural().hidden(), 32u);
  EXPECT_GT(resolved.neural().steps(), 0u);
  EXPECT_EQ(resolved.view_directions(), 81u);
  EXPECT_TRUE(Validate(resolved, "precompute").empty());

  const auto issues_of = [&](const char* field, uint32_t value) {
    v1::PrecomputeSettings bad = resolved;
    const auto* descriptor = bad.neural().GetDescriptor()->FindFieldByName(field);
    bad.mutable_neural()->GetReflection()->SetUInt32(bad.mutable_neural(), descriptor, value);
    std::string text;
    for (const ValidationIssue& issue : Validate(bad, "precompute")) text += issue.ToString() + "\n";
    return text;
  };
  EXPECT_EQ(issues_of("channels", 6), "precompute.neural.channels: 6 is not a multiple of 4\n");
  EXPECT_EQ(issues_of("channels", 20), "precompute.neural.channels: 20 exceeds 16\n");
  EXPECT_EQ(issues_of("hidden", 2), "precompute.neural.hidden: 2 is below 4\nprecompute.neural.hidden: 2 is not a "
                                    "multiple of 4\n");
  EXPECT_EQ(issues_of("hidden", 128), "precompute.neural.hidden: 128 exceeds 64\n");
  EXPECT_EQ(issues_of("steps", 2000000), "precompute.neural.steps: 2000000 exceeds 1000000\n");
  EXPECT_EQ(issues_of("base_rank", 9), "precompute.neural.base_rank: 9 exceeds 8\n");
  EXPECT_EQ(resolved.neural().base_rank(), 0u);

  v1::FabricSpec fabric;
  fabric.mutable_knit();
  const std::string key = FabricKey(fabric, settings);
  for (const char* field : {"channels", "hidden", "steps", "base_rank"}) {
    v1::PrecomputeSettings changed = resolved;
    const auto* descriptor = changed.neural().GetDescriptor()->FindFieldByName(field);
    changed.mutable_neural()->GetReflection()->SetUInt32(changed.mutable_neural(), descriptor, 4);
    EXPECT_NE(FabricKey(fabric, changed), key) << field;
  }
  v1::PrecomputeSettings seeded = settings;
  seeded.set_seed(3);
  EXPECT_NE(FabricKey(fabric, seeded), key);
  v1::PrecomputeSettings with_fit = resolved;
  with_fit.set_lobes(3);  // svbrdf's fit: not the neural asset's
  with_fit.mutable_factored()->set_rank(2);
  EXPECT_EQ(FabricKey(fabric, with_fit), key);
  // The other methods ignore the neural settings.
  for (v1::FabricMethod other : {v1::FABRIC_METHOD_SVBRDF, v1::FABRIC_METHOD_TABULATED, v1::FABRIC_METHOD_FACTORED}) {
    v1::PrecomputeSettings plain, with_neural;
    plain.set_method(other);
    with_neural = plain;
    with_neural.mutable_neural()->set_channels(4);
    EXPECT_EQ(FabricKey(fabric, plain), FabricKey(fabric, with_neural)) << other;
  }
}

}  // namespace
}  // namespace loom
