#include "core/fit/fabric_asset.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>

#include "core/acquire/hemisphere_directions.h"
#include "core/util/error.h"
#include "core/util/file_io.h"

namespace loom {
namespace {

// A small fitted fabric: 4×4 texels, 4×4 views and lights, a glossy BRDF that
// varies across the tile, one texel empty.
FittedFabric SmallFabric(v1::MipLevels mip_levels = v1::MIP_LEVELS_AUTO) {
  RadianceSamples samples(4, HemisphereGridDirections(16), HemisphereGridDirections(16));
  for (size_t texel = 0; texel < samples.texel_count(); ++texel) {
    LafortuneBrdf brdf;
    brdf.lobe_count = 1;
    brdf.rho = glm::vec3(0.1f + 0.02f * texel, 0.2f, 0.3f);
    brdf.lobes[0] = {glm::vec3(-1.0f), glm::vec3(-0.9f), glm::vec3(0.9f), glm::vec3(8.0f)};
    for (size_t v = 0; v < samples.view_count(); ++v) {
      samples.alpha[samples.AlphaIndex(texel, v)] = texel == 6 ? 0.0f : 1.0f - 0.05f * float(v % 3);
      if (texel == 6) continue;
      for (size_t l = 0; l < samples.light_count(); ++l) {
        samples.radiance[samples.RadianceIndex(texel, v, l)] =
            brdf.Evaluate(samples.light_directions[l], samples.view_directions[v]);
      }
    }
  }
  v1::PrecomputeSettings settings;
  settings.set_lobes(2);
  settings.set_mip_levels(mip_levels);
  FittedFabric fitted = FitFabric(samples, settings);
  for (size_t view = 0; view < fitted.view_heights.size(); ++view) {
    fitted.view_heights[view] = 0.0625f + 0.001f * static_cast<float>(view);
  }
  return fitted;
}

class FabricAssetTest : public ::testing::Test {
 protected:
  void SetUp() override {
    directory_ = std::filesystem::temp_directory_path() /
                 ("loom_fabric_asset_test_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
                  "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(directory_);
  }
  void TearDown() override { std::filesystem::remove_all(directory_); }
  std::filesystem::path directory_;
};

void ExpectSameLevels(const FittedFabric& a, const FittedFabric& b, float tolerance) {
  auto near = [tolerance](float x, float y) { return std::abs(x - y) <= tolerance * std::max(1.0f, std::abs(y)); };
  ASSERT_EQ(a.levels.size(), b.levels.size());
  EXPECT_EQ(a.lobes, b.lobes);
  EXPECT_EQ(a.view_directions, b.view_directions);
  EXPECT_EQ(a.view_heights, b.view_heights);
  for (size_t k = 0; k < a.levels.size(); ++k) {
    const FittedLevel& x = a.levels[k];
    const FittedLevel& y = b.levels[k];
    ASSERT_EQ(x.resolution, y.resolution);
    EXPECT_EQ(x.status, y.status);
    EXPECT_EQ(x.stats.samples, y.stats.samples);
    EXPECT_EQ(x.stats.relative_rmse, y.stats.relative_rmse);
    for (size_t t = 0; t < x.brdfs.size(); ++t) {
      for (int c = 0; c < 3; ++c) {
        EXPECT_TRUE(near(x.brdfs[t].rho[c], y.brdfs[t].rho[c])) << "level " << k << " texel " << t;
        for (uint32_t i = 0; i < a.lobes; ++i) {
          EXPECT_TRUE(near(x.brdfs[t].lobes[i].cx[c], y.brdfs[t].lobes[i].cx[c]));
          EXPECT_TRUE(near(x.brdfs[t].lobes[i].n[c], y.brdfs[t].lobes[i].n[c]));
        }
        EXPECT_TRUE(near(x.normals[t][c], y.normals[t][c]));
        EXPECT_TRUE(near(x.tangents[t][c], y.tangents[t][c]));
      }
      EXPECT_TRUE(near(x.rmse[t], y.rmse[t]));
    }
    for (size_t i = 0; i < x.lut.size(); ++i) {
      for (int c = 0; c < 3; ++c) EXPECT_TRUE(near(x.lut[i][c], y.lut[i][c])) << "level " << k << " entry " << i;
      EXPECT_TRUE(near(x.alpha[i], y.alpha[i]));
    }
  }
}

TEST_F(FabricAssetTest, FullFloatRoundTripGivesBackTheSameNumbers) {
  const FittedFabric fabric = SmallFabric();
  v1::PrecomputeSettings settings;
  settings.set_half_float(false);
  WriteFabricAsset(fabric, settings, "fabric-key-1", directory_);
  ExpectSameLevels(ReadFabricAsset(directory_), fabric, 0.0f);

  const nlohmann::json manifest = nlohmann::json::parse(ReadFile(directory_ / "manifest.json"));
  EXPECT_EQ(manifest.at("fabric_key"), "fabric-key-1");
  EXPECT_EQ(manifest.at("asset_version"), kAssetFormatVersion);
  EXPECT_EQ(manifest.at("fitted_levels"), 3);
  size_t files = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(directory_)) ++files;
  EXPECT_EQ(files, 3u) << "no temporary file left behind";
}

TEST_F(FabricAssetTest, HalfFloatRoundTripIsWithinHalfPrecision) {
  const FittedFabric fabric = SmallFabric();
  WriteFabricAsset(fabric, {}, "fabric-key-2", directory_);  // half floats by default
  const FittedFabric read = ReadFabricAsset(directory_);
  ExpectSameLevels(read, fabric, 1e-3f);
  // The lobe coefficients stay 32-bit: C^N turns half floats' rounding into
  // percent at high N.
  for (size_t k = 0; k < fabric.levels.size(); ++k) {
    for (size_t t = 0; t < fabric.levels[k].brdfs.size(); ++t) {
      for (uint32_t i = 0; i < fabric.lobes; ++i) {
        const LafortuneLobe& written = fabric.levels[k].brdfs[t].lobes[i];
        const LafortuneLobe& loaded = read.levels[k].brdfs[t].lobes[i];
        EXPECT_EQ(loaded.cx, written.cx) << "level " << k << " texel " << t << " lobe " << i;
        EXPECT_EQ(loaded.cy, written.cy) << "level " << k << " texel " << t << " lobe " << i;
        EXPECT_EQ(loaded.cz, written.cz) << "level " << k << " texel " << t << " lobe " << i;
      }
    }
  }
}

TEST_F(FabricAssetTest, SingleLevelRoundTrip) {
  const FittedFabric fabric = SmallFabric(v1::MIP_LEVELS_NONE);
  ASSERT_EQ(fabric.levels.size(), 1u);
  v1::PrecomputeSettings settings;
  settings.set_half_float(false);
  WriteFabricAsset(fabric, settings, "fabric-key-4", directory_);
  ExpectSameLevels(ReadFabricAsset(directory_), fabric, 0.0f);
}

TEST_F(FabricAssetTest, CorruptedImageIsDetected) {
  WriteFabricAsset(SmallFabric(), {}, "fabric-key-3", directory_);
  std::string bytes = ReadFile(directory_ / "lut.exr");
  bytes[bytes.size() / 2] ^= 0x5a;
  WriteFileAtomic(directory_ / "lut.exr", bytes);
  try {
    ReadFabricAsset(directory_);
    FAIL() << "a corrupted asset was read";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument);
    EXPECT_NE(std::string(e.what()).find("lut.exr is corrupted"), std::string::npos) << e.what();
  }
}

// A manifest names the sizes every allocation of the reader follows: each is
// checked against the caps and the level chain before anything is read.
TEST_F(FabricAssetTest, ManifestSizesOutsideTheCapsAreClearErrors) {
  WriteFabricAsset(SmallFabric(), {}, "fabric-key-5", directory_);
  const nlohmann::json good = nlohmann::json::parse(ReadFile(directory_ / "manifest.json"));
  const auto error_with = [&](const std::function<void(nlohmann::json&)>& edit) -> std::string {
    nlohmann::json manifest = good;
    edit(manifest);
    WriteFileAtomic(directory_ / "manifest.json", manifest.dump());
    try {
      ReadFabricAsset(directory_);
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument);
      return e.what();
    }
    return "read";
  };
  EXPECT_NE(error_with([](nlohmann::json& m) { m["lobes"] = 7; }).find("lobes 7 is not in [1, 3]"),
            std::string::npos);
  EXPECT_NE(error_with([](nlohmann::json& m) { m["view_directions"] = 1 << 20; }).find("view_directions 1048576"),
            std::string::npos);
  EXPECT_NE(error_with([](nlohmann::json& m) { m["levels"][0]["resolution"] = 100000; })
                .find("levels[0].resolution 100000 is not in [2, 256]"),
            std::string::npos);
  EXPECT_NE(error_with([](nlohmann::json& m) { m["levels"][1]["resolution"] = 3; })
                .find("levels[1].resolution 3 is not 2"),
            std::string::npos);
  EXPECT_NE(error_with([](nlohmann::json& m) { m["levels"].erase(1); }).find("2 levels for resolution 4"),
            std::string::npos);
  EXPECT_NE(error_with([](nlohmann::json& m) { m["lobes"] = "two"; }).find("is not a valid manifest"),
            std::string::npos);
  EXPECT_EQ(error_with([](nlohmann::json&) {}), "read");
}

TEST_F(FabricAssetTest, MissingAssetIsNotFound) {
  try {
    ReadFabricAsset(directory_);
    FAIL() << "read an asset that does not exist";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kNotFound);
  }
}

}  // namespace
}  // namespace loom
