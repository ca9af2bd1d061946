// Colour components (core/methods/colour_sheets.h): how the components are packed
// into sheets, and that with direct light the fabric's samples are the sum of its
// sheets' samples mapped by its colours, as eq. 8 of the neural woven paper says.

#include "core/methods/colour_sheets.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/acquire/acquisition.h"
#include "core/spec/defaults.h"
#include "core/spec/spec_json.h"

namespace loom {
namespace {

using Kind = ColourComponent::Kind;

TEST(ColourSheets, PackDiffuseThenSpecularThreeToASheet) {
  const std::vector<SheetChannels> one = ColourSheetChannels(1);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one[0][0], (ColourComponent{Kind::kDiffuse, 0}));
  EXPECT_EQ(one[0][1], (ColourComponent{Kind::kSpecular, 0}));
  EXPECT_FALSE(one[0][2].has_value());

  const std::vector<SheetChannels> two = ColourSheetChannels(2);  // the paper's C_warp, C_weft, S_warp, S_weft
  ASSERT_EQ(two.size(), 2u);
  EXPECT_EQ(two[0][1], (ColourComponent{Kind::kDiffuse, 1}));
  EXPECT_EQ(two[0][2], (ColourComponent{Kind::kSpecular, 0}));
  EXPECT_EQ(two[1][0], (ColourComponent{Kind::kSpecular, 1}));
  EXPECT_FALSE(two[1][1].has_value());
  EXPECT_EQ(ColourSheetChannels(3).size(), 2u);
  EXPECT_EQ(ColourSheetChannels(4).size(), 3u);
}

TEST(ColourSheets, JsonRoundTripsAndRefusesWhatIsNotAComponent) {
  const std::vector<SheetChannels> sheets = ColourSheetChannels(5);
  const nlohmann::json json = ColourSheetsJson(sheets);
  EXPECT_EQ(json[0][0], "diffuse 0");
  const auto invalid = [](const std::string& what) { return Error(ErrorCode::kInvalidArgument, what); };
  EXPECT_EQ(ParseColourSheets(json, invalid), sheets);
  for (const char* bad : {R"([])", R"({})", R"([["diffuse 0", "specular 0"]])", R"([["diffuse 0", "glossy 1", ""]])",
                          R"([["diffuse 99", "", ""]])", R"([[1, "", ""]])"}) {
    try {
      ParseColourSheets(nlohmann::json::parse(bad), invalid);
      ADD_FAILURE() << bad << " was accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument) << bad;
      EXPECT_NE(std::string(e.what()).find("colour sheets"), std::string::npos) << e.what();
    }
  }
}

v1::FabricSpec TwoColourWeave() {
  return WithDefaults(ParseSpecJson<v1::FabricSpec>(R"({
      "woven": {"pattern": "WEAVE_PATTERN_TWILL", "gap_ratio": 0.2, "warp_colours": [0], "weft_colours": [1]},
      "yarns": [{"shading": "YARN_SHADING_MICROFLAKE", "roughness": 0.3, "diffuse_transmission": 0.4,
                 "diffuse_albedo": {"r": 0.7, "g": 0.2, "b": 0.1}, "specular_albedo": {"r": 0.2, "g": 0.25, "b": 0.3}},
                {"roughness": 0.4, "diffuse_albedo": {"r": 0.1, "g": 0.3, "b": 0.6},
                 "specular_albedo": {"r": 0.1, "g": 0.1, "b": 0.1}}]})",
                                                    "fabric"));
}

TEST(ColourSheets, ColoursAreTheAlbedosOfTheChannelsComponents) {
  const v1::FabricSpec fabric = TwoColourWeave();
  const std::vector<SheetChannels> sheets = ColourSheetChannels(2);
  const glm::mat3 first = SheetColours(fabric, sheets[0]), second = SheetColours(fabric, sheets[1]);
  EXPECT_EQ(first[0], glm::vec3(0.7f, 0.2f, 0.1f));  // diffuse 0
  EXPECT_EQ(first[1], glm::vec3(0.1f, 0.3f, 0.6f));  // diffuse 1
  EXPECT_EQ(first[2], glm::vec3(0.2f, 0.25f, 0.3f)); // specular 0
  EXPECT_EQ(second[0], glm::vec3(0.1f));             // specular 1
  EXPECT_EQ(second[1], glm::vec3(0.0f));
  EXPECT_THROW(SheetColours(fabric, ColourSheetChannels(3)[0]), Error);  // no yarn 2
}

// Eq. 8 on the samples themselves: the two sheets of a two-yarn microflake twill,
// mapped by its colours and summed, are its samples, lit from the front and from
// behind. With one indirect bounce they are not (light reflected by two yarns is a
// product of their albedos): what the key rule (colour components need
// indirect_bounces 0) protects.
double LargestDifferenceFromTheSheets(uint32_t bounces, LightSide side) {
  const v1::FabricSpec fabric = TwoColourWeave();
  const FabricTile tile = BuildFabricTile(fabric);
  v1::PrecomputeSettings settings = ParseSpecJson<v1::PrecomputeSettings>(
      R"({"spatial_resolution": 8, "view_directions": 16, "light_directions": 16, "supersampling": 1})", "precompute");
  settings.set_indirect_bounces(bounces);
  const RadianceSamples whole = Acquire(tile, settings, {}, nullptr, {}, side);
  std::vector<glm::vec3> summed(whole.radiance.size(), glm::vec3(0.0f));
  for (const SheetChannels& sheet : ColourSheetChannels(fabric.yarns_size())) {
    const RadianceSamples part = Acquire(ComponentTile(tile, sheet), settings, {}, nullptr, {}, side);
    EXPECT_EQ(part.alpha, whole.alpha);
    const glm::mat3 colours = SheetColours(fabric, sheet);
    for (size_t i = 0; i < summed.size(); ++i) summed[i] += colours * part.radiance[i];
  }
  double largest = 0.0, brightest = 0.0;
  for (size_t i = 0; i < summed.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      largest = std::max(largest, double{std::abs(summed[i][c] - whole.radiance[i][c])});
      brightest = std::max(brightest, double{whole.radiance[i][c]});
    }
  }
  EXPECT_GT(brightest, 0.01);
  return largest;
}

TEST(ColourSheets, WithDirectLightTheSamplesAreTheSheetsMappedByTheColours) {
  EXPECT_LT(LargestDifferenceFromTheSheets(0, LightSide::kFront), 1e-5);
  EXPECT_LT(LargestDifferenceFromTheSheets(0, LightSide::kBack), 1e-5);
}

TEST(ColourSheets, WithIndirectLightTheyAreNot) {
  EXPECT_GT(LargestDifferenceFromTheSheets(1, LightSide::kFront), 1e-3);
}

}  // namespace
}  // namespace loom
