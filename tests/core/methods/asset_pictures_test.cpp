#include "core/methods/asset_pictures.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "core/methods/fabric_method.h"
#include "core/methods/svbrdf/svbrdf_method.h"
#include "core/methods/tabulated/tabulated_method.h"
#include "core/spec/defaults.h"
#include "core/util/file_io.h"
#include "tests/core/methods/method_test_data.h"

namespace loom {
namespace {

TEST(TexelPicture, ScalesAsAskedAndStaysInTheUnitRange) {
  const auto ramp = [](size_t texel) { return glm::vec3(0.5f * texel, 2.0f - texel, 1.0f); };
  const Image reflectance = TexelPicture(2, ramp, PictureScale::kReflectance);
  ASSERT_EQ(reflectance.width, 2);
  ASSERT_EQ(reflectance.height, 2);
  EXPECT_FLOAT_EQ(reflectance.at(1, 0, 0), 0.5f);  // texel 1
  EXPECT_FLOAT_EQ(reflectance.at(1, 1, 0), 1.0f);  // texel 3: 1.5 clamped
  EXPECT_FLOAT_EQ(reflectance.at(1, 1, 1), 0.0f);  // -1 clamped
  const Image maximum = TexelPicture(2, ramp, PictureScale::kMaximum);  // largest value 2
  EXPECT_FLOAT_EQ(maximum.at(1, 1, 0), 0.75f);
  EXPECT_FLOAT_EQ(maximum.at(0, 0, 1), 1.0f);
  EXPECT_FLOAT_EQ(maximum.at(0, 0, 2), 0.5f);
  const Image range = TexelPicture(2, ramp, PictureScale::kRange);  // each channel on its own
  EXPECT_FLOAT_EQ(range.at(1, 0, 0), 1.0f / 3.0f);
  EXPECT_FLOAT_EQ(range.at(0, 1, 1), 1.0f / 3.0f);  // texel 2: 0 in [-1, 2]
  EXPECT_FLOAT_EQ(range.at(0, 0, 2), 0.5f);        // a constant channel
  const Image black = TexelPicture(2, [](size_t) { return glm::vec3(0.0f); }, PictureScale::kMaximum);
  for (float p : black.pixels) EXPECT_EQ(p, 0.0f);
}

TEST(TopDirection, IsTheDirectionNearestTheNormal) {
  EXPECT_EQ(TopDirection({{0.6f, 0.0f, 0.8f}, {0.0f, 0.1f, 0.99f}, {0.0f, 0.8f, 0.6f}}), 1u);
}

// Every method's pictures: each level's maps at the level's resolution, in [0, 1],
// the coverage alpha the asset's own at the view from above (the samples have holes
// that differ per view), written as PNGs with a list naming each.
class MethodPictures : public testing::TestWithParam<const char*> {};

TEST_P(MethodPictures, ShowEveryLevelsMapsFromAboveAndAreWrittenWithTheirList) {
  const RadianceSamples samples = SyntheticSamples(4, 16, 16, true);
  v1::PrecomputeSettings settings;
  settings.set_method(MethodNamed(GetParam())->id());
  settings.set_lobes(1);
  settings.mutable_neural()->set_steps(20);
  const std::unique_ptr<FabricAsset> asset = MethodNamed(GetParam())->Build(samples, WithDefaults(settings), {});
  const std::vector<AssetPicture> pictures = asset->Pictures();

  const size_t top = TopDirection(samples.view_directions);
  std::map<uint32_t, std::set<std::string>> maps;
  for (const AssetPicture& picture : pictures) {
    const int side = static_cast<int>(samples.resolution >> picture.level);
    ASSERT_EQ(picture.image.width, side) << picture.map;
    ASSERT_EQ(picture.image.height, side) << picture.map;
    ASSERT_EQ(picture.image.channels, 3) << picture.map;
    EXPECT_FALSE(picture.caption.empty()) << picture.map;
    for (float p : picture.image.pixels) ASSERT_TRUE(p >= 0.0f && p <= 1.0f) << picture.map << " " << p;
    EXPECT_TRUE(maps[picture.level].insert(picture.map).second) << picture.map << " twice";
    if (picture.level == 0 && picture.map == "alpha") {
      for (int y = 0; y < side; ++y) {
        for (int x = 0; x < side; ++x) {
          const size_t texel = static_cast<size_t>(y) * side + x;
          EXPECT_FLOAT_EQ(picture.image.at(x, y, 0), samples.alpha[samples.AlphaIndex(texel, top)]) << texel;
        }
      }
    }
  }
  ASSERT_EQ(maps.size(), 3u);  // levels of 4², 2², 1²
  for (const auto& [level, names] : maps) {
    EXPECT_TRUE(names.count("alpha")) << level;
    EXPECT_GE(names.size(), 3u) << level;
  }

  const auto directory = std::filesystem::temp_directory_path() / ("loom-pictures-" + std::string(GetParam()));
  std::filesystem::remove_all(directory);
  std::filesystem::create_directories(directory);
  WriteAssetPictures(*asset, directory);
  const nlohmann::json list = nlohmann::json::parse(ReadFile(directory / kAssetPicturesFile));
  ASSERT_EQ(list.size(), pictures.size());
  for (size_t i = 0; i < pictures.size(); ++i) {
    EXPECT_EQ(list[i]["file"], AssetPictureFile(pictures[i].level, pictures[i].map));
    EXPECT_EQ(list[i]["level"], pictures[i].level);
    EXPECT_EQ(list[i]["caption"], pictures[i].caption);
    const Image read = ReadImage(directory / list[i]["file"].get<std::string>());
    EXPECT_EQ(read.width, pictures[i].image.width);
  }
  std::filesystem::remove_all(directory);
}

INSTANTIATE_TEST_SUITE_P(EveryMethod, MethodPictures, testing::Values("svbrdf", "tabulated", "factored", "neural"));

// The svbrdf's albedo picture is ρ_d as fitted; tabulated's radiance picture is the
// table seen and lit from above, scaled to its maximum.
TEST(MethodPictureValues, AreTheMethodsOwn) {
  const RadianceSamples samples = SyntheticSamples(4, 16, 16, true);
  v1::PrecomputeSettings settings;
  settings.set_lobes(1);
  const std::unique_ptr<FabricAsset> fitted = SvbrdfMethod().Build(samples, WithDefaults(settings), {});
  const auto& svbrdf = static_cast<const SvbrdfAsset&>(*fitted);
  int checked = 0;
  for (const AssetPicture& picture : svbrdf.Pictures()) {
    if (picture.level != 1 || picture.map != "albedo") continue;
    const glm::vec3 rho = svbrdf.fit().levels[1].brdfs[3].rho;  // texel (1, 1)
    EXPECT_NEAR(picture.image.at(1, 1, 0), std::min(rho.x, 1.0f), 1e-6f);
    EXPECT_NEAR(picture.image.at(1, 1, 2), std::min(rho.z, 1.0f), 1e-6f);
    ++checked;
  }
  settings.set_method(v1::FABRIC_METHOD_TABULATED);
  const std::unique_ptr<FabricAsset> table_asset = TabulatedMethod().Build(samples, WithDefaults(settings), {});
  const auto& tabulated = static_cast<const TabulatedAsset&>(*table_asset);
  const TabulatedFabric& table = tabulated.fabric();
  const size_t view = TopDirection(table.view_directions), light = TopDirection(table.light_directions);
  const size_t views = table.view_count(), lights = table.light_count();
  float largest = 0.0f;
  for (size_t texel = 0; texel < 16; ++texel) {
    const glm::vec3 v = table.levels[0].radiance[(texel * views + view) * lights + light];
    largest = std::max({largest, v.x, v.y, v.z});
  }
  const glm::vec3 texel5 = table.levels[0].radiance[(5 * views + view) * lights + light];
  for (const AssetPicture& picture : tabulated.Pictures()) {
    if (picture.level != 0 || picture.map != "radiance") continue;
    EXPECT_NEAR(picture.image.at(1, 1, 1), texel5.y / largest, 1e-6f);
    ++checked;
  }
  EXPECT_EQ(checked, 2);
}

}  // namespace
}  // namespace loom
