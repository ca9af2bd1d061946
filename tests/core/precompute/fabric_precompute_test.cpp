#include "core/precompute/fabric_precompute.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include <unistd.h>

#include "core/methods/fabric_method.h"
#include "core/spec/fabric_key.h"
#include "core/spec/spec_json.h"
#include "core/util/error.h"

namespace loom {
namespace {

// A plain weave of one yarn shaded `shading`.
v1::FabricSpec Weave(const std::string& shading) {
  return ParseSpecJson<v1::FabricSpec>(
      R"({"woven": {}, "yarns": [{"shading": ")" + shading + R"(", "diffuse_transmission": 0.5}]})", "fabric");
}

v1::FabricSpec KajiyaKayWeave() { return ParseSpecJson<v1::FabricSpec>(R"({"woven": {}})", "fabric"); }

// Small enough for a test: 8×8 texels, 4×4 views and lights, a short training.
v1::PrecomputeSettings Small(v1::FabricMethod method) {
  v1::PrecomputeSettings settings;
  settings.set_method(method);
  settings.mutable_neural()->set_steps(50);  // the other methods ignore it
  settings.set_spatial_resolution(8);
  settings.set_view_directions(16);
  settings.set_light_directions(16);
  settings.set_supersampling(1);
  return settings;
}

class FabricPrecomputeTest : public ::testing::TestWithParam<v1::FabricMethod> {
 protected:
  void SetUp() override {
    directory_ = std::filesystem::temp_directory_path() /
                 ("loom-precompute-test-" + std::to_string(::getpid()) + "-" +
                  ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(directory_);
  }
  void TearDown() override { std::filesystem::remove_all(directory_); }

  // The names of the back sheet's files in directory_.
  int BackSheetFiles() const {
    int count = 0;
    for (const auto& entry : std::filesystem::directory_iterator(directory_)) {
      count += entry.path().filename().string().rfind(kBackSheetPrefix, 0) == 0;
    }
    return count;
  }

  std::filesystem::path directory_;
};

// A microflake weave transmits: its asset has a back sheet of the same method,
// lit from behind, which the cache's round trip keeps.
TEST_P(FabricPrecomputeTest, MicroflakeWeaveHasABackSheetThatSurvivesTheRoundTrip) {
  const v1::FabricSpec fabric = Weave("YARN_SHADING_MICROFLAKE");
  const v1::PrecomputeSettings settings = Small(GetParam());
  const std::unique_ptr<FabricAsset> asset = PrecomputeAsset(fabric, settings);
  ASSERT_NE(asset->back(), nullptr);
  EXPECT_EQ(&asset->back()->method(), &asset->method());
  EXPECT_EQ(asset->back()->back(), nullptr);

  asset->Write(settings, FabricKey(fabric, settings), directory_);
  EXPECT_GT(BackSheetFiles(), 0);
  const std::unique_ptr<FabricAsset> read = ReadAnyFabricAsset(directory_);
  ASSERT_NE(read->back(), nullptr);
  EXPECT_EQ(read->back()->Figures()["method"], asset->back()->Figures()["method"]);
}

// Kajiya–Kay yarns do not transmit, and transmission = false turns it off for any
// yarn: no back sheet, no back files, and a manifest that reads back without one.
TEST_P(FabricPrecomputeTest, NoBackSheetWithoutTransmission) {
  v1::PrecomputeSettings settings = Small(GetParam());
  const std::unique_ptr<FabricAsset> kajiya_kay = PrecomputeAsset(KajiyaKayWeave(), settings);
  EXPECT_EQ(kajiya_kay->back(), nullptr);

  settings.set_transmission(false);
  const v1::FabricSpec microflake = Weave("YARN_SHADING_MICROFLAKE");
  const std::unique_ptr<FabricAsset> asset = PrecomputeAsset(microflake, settings);
  EXPECT_EQ(asset->back(), nullptr);
  asset->Write(settings, FabricKey(microflake, settings), directory_);
  EXPECT_EQ(BackSheetFiles(), 0);
  EXPECT_EQ(ReadAnyFabricAsset(directory_)->back(), nullptr);
}

// A back sheet the manifest promises but the directory lacks is an error, not a
// fabric that silently stops transmitting.
TEST_P(FabricPrecomputeTest, MissingBackSheetIsNotFound) {
  const v1::FabricSpec fabric = Weave("YARN_SHADING_MICROFLAKE");
  const v1::PrecomputeSettings settings = Small(GetParam());
  PrecomputeAsset(fabric, settings)->Write(settings, FabricKey(fabric, settings), directory_);
  for (const auto& entry : std::filesystem::directory_iterator(directory_)) {
    if (entry.path().filename().string().rfind(kBackSheetPrefix, 0) == 0) std::filesystem::remove(entry.path());
  }
  try {
    ReadAnyFabricAsset(directory_);
    FAIL() << "read an asset whose back sheet is missing";
  } catch (const Error& error) {
    EXPECT_EQ(error.code(), ErrorCode::kNotFound) << error.what();
  }
}

INSTANTIATE_TEST_SUITE_P(EveryMethod, FabricPrecomputeTest,
                         ::testing::Values(v1::FABRIC_METHOD_SVBRDF, v1::FABRIC_METHOD_TABULATED,
                                           v1::FABRIC_METHOD_FACTORED, v1::FABRIC_METHOD_NEURAL),
                         [](const auto& info) { return std::string(v1::FabricMethod_Name(info.param)).substr(14); });

}  // namespace
}  // namespace loom
