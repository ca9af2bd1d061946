// The tabulated method: its levels from samples, its asset on disk, its cache key,
// and its GLSL lookup against the C++ one (EvaluateTabulated) per pixel.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "core/acquire/hemisphere_directions.h"
#include "core/methods/fabric_method.h"
#include "core/methods/tabulated/tabulated_method.h"
#include "core/spec/defaults.h"
#include "core/spec/fabric_key.h"
#include "core/spec/spec_json.h"
#include "core/spec/validate.h"
#include "core/util/error.h"
#include "tests/core/methods/method_test_data.h"
#include "tests/core/methods/plane_probe.h"

namespace loom {
namespace {

TEST(TabulatedFabric, LevelZeroHoldsTheSamplesAndReturnsThemAtTheStoredDirections) {
  const RadianceSamples samples = SyntheticSamples(4, 16, 16, false);
  const TabulatedFabric fabric = TabulateFabric(WithViewHeights(samples, 0.1f), true);
  ASSERT_EQ(fabric.levels.size(), 3u);
  for (size_t texel = 0; texel < samples.texel_count(); ++texel) {
    for (size_t view = 0; view < samples.view_count(); ++view) {
      for (size_t light = 0; light < samples.light_count(); ++light) {
        const glm::vec4 value = EvaluateTabulated(fabric, 0, texel, samples.view_directions[view],
                                                  samples.light_directions[light]);
        const glm::vec3 expected = samples.radiance[samples.RadianceIndex(texel, view, light)];
        for (int c = 0; c < 3; ++c) ASSERT_NEAR(value[c], expected[c], 1e-5f * (1.0f + expected[c]));
        ASSERT_NEAR(value.a, samples.alpha[samples.AlphaIndex(texel, view)], 1e-6f);
      }
    }
  }
}

TEST(TabulatedFabric, ACoarseTexelPoolsItsChildrenWeightedByAlphaAndFillsItsHolesFromItsParent) {
  const RadianceSamples samples = SyntheticSamples(4, 16, 16, true);
  const TabulatedFabric fabric = TabulateFabric(samples, true);
  const size_t views = samples.view_count(), lights = samples.light_count();
  const TabulatedLevel& level1 = fabric.levels[1];
  size_t filled = 0;
  for (size_t texel = 0; texel < level1.texel_count(); ++texel) {
    const size_t x = texel % 2, y = texel / 2;
    for (size_t view = 0; view < views; ++view) {
      float alpha_sum = 0.0f;
      std::vector<glm::vec3> sum(lights, glm::vec3(0.0f));
      for (size_t child = 0; child < 4; ++child) {
        const size_t fine = (2 * y + child / 2) * 4 + 2 * x + child % 2;
        const float alpha = samples.alpha[samples.AlphaIndex(fine, view)];
        alpha_sum += alpha;
        for (size_t light = 0; light < lights; ++light) {
          sum[light] += alpha * samples.radiance[samples.RadianceIndex(fine, view, light)];
        }
      }
      ASSERT_NEAR(level1.alpha[texel * views + view], alpha_sum / 4.0f, 1e-6f);
      for (size_t light = 0; light < lights; ++light) {
        const glm::vec3 expected = sum[light] / alpha_sum;
        const glm::vec3 got = level1.radiance[(texel * views + view) * lights + light];
        for (int c = 0; c < 3; ++c) ASSERT_NEAR(got[c], expected[c], 1e-5f);
      }
    }
  }
  // Level 0's empty (texel, view) pairs take their parent's radiance.
  const TabulatedLevel& level0 = fabric.levels[0];
  for (size_t texel = 0; texel < level0.texel_count(); ++texel) {
    const size_t parent = (texel / 4 / 2) * 2 + (texel % 4) / 2;
    for (size_t view = 0; view < views; ++view) {
      if (level0.alpha[texel * views + view] > 0.0f) continue;
      ++filled;
      for (size_t light = 0; light < lights; ++light) {
        ASSERT_EQ(level0.radiance[(texel * views + view) * lights + light],
                  level1.radiance[(parent * views + view) * lights + light]);
      }
    }
  }
  EXPECT_GT(filled, 0u);
  // The ambient response: 2π/L times the sum over lights.
  const glm::vec3 ambient = fabric.levels[2].ambient[3];
  glm::vec3 sum(0.0f);
  for (size_t light = 0; light < lights; ++light) sum += fabric.levels[2].radiance[3 * lights + light];
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(ambient[c], 2.0f * std::numbers::pi_v<float> / lights * sum[c], 1e-5f);
}

TEST(TabulatedFabric, LightsBelowTheHorizonGiveNothingAndFadePastTheOutermostRing) {
  const TabulatedFabric fabric = TabulateFabric(SyntheticSamples(2, 16, 16, false), false);
  const glm::vec3 view(0.0f, 0.0f, 1.0f);
  EXPECT_EQ(glm::vec3(EvaluateTabulated(fabric, 0, 0, view, glm::normalize(glm::vec3(1, 0, -0.1f)))), glm::vec3(0.0f));
  // Grazing: past the outermost ring (k = 4: at about 61° from the normal) towards the horizon.
  const glm::vec3 ring = glm::vec3(EvaluateTabulated(fabric, 0, 0, view, fabric.light_directions[7]));
  const glm::vec3 near_horizon =
      glm::vec3(EvaluateTabulated(fabric, 0, 0, view, glm::normalize(glm::vec3(1.0f, 0.0f, 0.02f))));
  EXPECT_GT(ring.r, 0.0f);
  EXPECT_LT(near_horizon.r, 0.1f * ring.r);
}

class TabulatedAssetTest : public ::testing::Test {
 protected:
  void SetUp() override {
    directory_ = std::filesystem::temp_directory_path() /
                 ("loom-tabulated-" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    std::filesystem::remove_all(directory_);
  }
  void TearDown() override { std::filesystem::remove_all(directory_); }
  std::filesystem::path directory_;
};

TEST_F(TabulatedAssetTest, RoundTripsExactlyInFullFloatsAndWithinHalfPrecisionOtherwise) {
  const TabulatedAsset asset(TabulateFabric(WithViewHeights(SyntheticSamples(4, 16, 9, true), 0.125f), true));
  for (const bool half : {false, true}) {
    SCOPED_TRACE(half ? "half" : "full");
    v1::PrecomputeSettings settings;
    settings.set_method(v1::FABRIC_METHOD_TABULATED);
    settings.set_half_float(half);
    std::filesystem::remove_all(directory_);
    asset.Write(settings, "key", directory_);
    const std::unique_ptr<FabricAsset> read = ReadAnyFabricAsset(directory_);
    ASSERT_EQ(&read->method(), &TabulatedMethod());
    const TabulatedFabric& a = asset.fabric();
    const TabulatedFabric& b = static_cast<const TabulatedAsset&>(*read).fabric();
    ASSERT_EQ(b.levels.size(), a.levels.size());
    EXPECT_EQ(b.light_count(), 9u);
    EXPECT_EQ(b.view_heights, a.view_heights);
    const float tolerance = half ? 1e-3f : 0.0f;
    for (size_t j = 0; j < a.levels.size(); ++j) {
      for (size_t i = 0; i < a.levels[j].radiance.size(); ++i) {
        for (int c = 0; c < 3; ++c) {
          ASSERT_NEAR(b.levels[j].radiance[i][c], a.levels[j].radiance[i][c], tolerance * a.levels[j].radiance[i][c]);
        }
      }
      for (size_t i = 0; i < a.levels[j].alpha.size(); ++i) {
        ASSERT_NEAR(b.levels[j].alpha[i], a.levels[j].alpha[i], tolerance);
        ASSERT_NEAR(b.levels[j].ambient[i].g, a.levels[j].ambient[i].g, tolerance * a.levels[j].ambient[i].g);
      }
    }
  }
}

TEST_F(TabulatedAssetTest, ACorruptedTableIsRefusedNamingTheFile) {
  TabulatedAsset(TabulateFabric(SyntheticSamples(2, 4, 4, false), true)).Write({}, "key", directory_);
  std::string bytes;
  {
    std::ifstream in(directory_ / "table.exr", std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  bytes[bytes.size() / 2] ^= 0x5a;
  std::ofstream(directory_ / "table.exr", std::ios::binary) << bytes;
  try {
    ReadAnyFabricAsset(directory_);
    FAIL() << "read a corrupted table";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument);
    EXPECT_NE(std::string(e.what()).find("table.exr is corrupted"), std::string::npos) << e.what();
  }
}

TEST(TabulatedKey, TheKeyChangesWithTheMethodAndIgnoresSvbrdfsFitSettings) {
  v1::FabricSpec fabric;
  fabric.mutable_knit();
  v1::PrecomputeSettings svbrdf, tabulated;
  tabulated.set_method(v1::FABRIC_METHOD_TABULATED);
  EXPECT_NE(FabricKey(fabric, svbrdf), FabricKey(fabric, tabulated));
  v1::PrecomputeSettings three_lobes = tabulated;
  three_lobes.set_lobes(3);
  three_lobes.set_max_lm_iterations(7);
  EXPECT_EQ(FabricKey(fabric, tabulated), FabricKey(fabric, three_lobes));
  v1::PrecomputeSettings finer = tabulated;
  finer.set_light_directions(256);
  EXPECT_NE(FabricKey(fabric, tabulated), FabricKey(fabric, finer));
  // svbrdf keys as before methods: no method field, whether it is named or not.
  v1::PrecomputeSettings named = svbrdf;
  named.set_method(v1::FABRIC_METHOD_SVBRDF);
  EXPECT_EQ(FabricKey(fabric, svbrdf), FabricKey(fabric, named));
  EXPECT_EQ(CanonicalFabricJson(fabric, svbrdf).find("method"), std::string::npos);
  three_lobes.set_method(v1::FABRIC_METHOD_SVBRDF);
  EXPECT_NE(FabricKey(fabric, svbrdf), FabricKey(fabric, three_lobes));
}

TEST(TabulatedKey, MoreSamplesThanTabulatedsCapAreRefused) {
  v1::PrecomputeSettings settings;
  settings.set_method(v1::FABRIC_METHOD_TABULATED);
  EXPECT_TRUE(Validate(WithDefaults(settings), "precompute").empty());  // the defaults, 64² × 81 × 64
  settings.set_spatial_resolution(64);
  settings.set_view_directions(81);
  settings.set_light_directions(100);
  EXPECT_TRUE(Validate(WithDefaults(settings), "precompute").empty());  // 64² × 81 × 100: 0.99 of the cap
  settings.set_light_directions(121);
  const ValidationIssues issues = Validate(WithDefaults(settings), "precompute");
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_NE(issues[0].message.find("exceeds 33554432, the cap of the table methods"), std::string::npos) << issues[0].message;
  settings.set_method(v1::FABRIC_METHOD_SVBRDF);
  EXPECT_TRUE(Validate(WithDefaults(settings), "precompute").empty());
}

TEST(TabulatedKey, AnUnknownMethodIsRefusedNamingTheField) {
  v1::PrecomputeSettings settings = WithDefaults(v1::PrecomputeSettings());
  settings.set_method(static_cast<v1::FabricMethod>(9));
  const ValidationIssues issues = Validate(settings, "precompute");
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].path, "precompute.method");
  EXPECT_NE(issues[0].message.find("9 is not a known FabricMethod value"), std::string::npos) << issues[0].message;
}

// The GLSL lookup (tile coordinate with parallax, texel, view grid, light grid, both
// bilinear interpolations, the view atlas's alpha) equals the C++ one per pixel.
TEST(TabulatedRender, GlslEqualsTheCppLookupPerPixel) {
  const TabulatedFabric fabric = TabulateFabric(WithViewHeights(SyntheticSamples(4, 64, 64, false), 0.05f), true);
  const PlaneProbe probe = ProbePlane(TabulatedAsset(TabulatedFabric(fabric)), 4, fabric.view_heights,
                                      [&](size_t texel, glm::vec3 view, glm::vec3 light) {
                                        return EvaluateTabulated(fabric, 0, texel, view, light);
                                      });
  EXPECT_GT(probe.compared, 96 * 64 / 5);
  EXPECT_LT(probe.worst, 1e-3) << "over " << probe.compared << " pixels";
  std::printf("compared %d pixels, worst relative error %.5f%%\n", probe.compared, 100.0 * probe.worst);
}

}  // namespace
}  // namespace loom
