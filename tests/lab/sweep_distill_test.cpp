#include "lab/sweep_distill.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/util/error.h"

namespace loom::lab {
namespace {

// A sweep CSV with the columns DistillSweep reads.
CsvTable Table(std::vector<std::vector<std::string>> rows) {
  CsvTable table;
  table.columns = {"configuration", "scene",         "method",        "footprint_pixels", "fabric_kind", "psnr_db",
                   "precompute_cpu_seconds", "asset_bytes", "spatial_resolution", "view_directions",
                   "light_directions",   "lobes",       "lookup_table",  "supersampling",    "level_mode",
                   "msaa_samples"};
  table.rows = std::move(rows);
  return table;
}

// One svbrdf row: `settings` = resolution, views, lights, lobes, LUT, supersampling.
std::vector<std::string> Row(const std::string& configuration, const std::string& scene, double footprint,
                             double psnr, double seconds, double bytes, std::vector<std::string> settings,
                             const std::string& level = "TRILINEAR", const std::string& kind = "knit-matte") {
  std::vector<std::string> row = {configuration, scene, "svbrdf", std::to_string(footprint), kind, std::to_string(psnr),
                                  std::to_string(seconds), std::to_string(bytes)};
  row.insert(row.end(), settings.begin(), settings.end());
  row.push_back(level);
  row.push_back("4");
  return row;
}

const std::vector<std::string> kDefault = {"32", "64", "64", "2", "1", "2"};
const std::vector<std::string> kLobes1 = {"32", "64", "64", "1", "1", "2"};

TEST(SweepDistill, MeansPerFootprintClassAgainstTheBaselineOnTheSameScenes) {
  const CsvTable table = Table({
      Row("default", "a", 64, 20, 10, 100, kDefault),
      Row("default", "b", 60, 22, 10, 100, kDefault),
      Row("default", "c", 2, 30, 10, 100, kDefault),
      Row("lobes1", "a", 64, 19, 5, 90, {"32", "64", "64", "1", "1", "2"}),
      Row("lobes1", "b", 60, 22, 5, 90, {"32", "64", "64", "1", "1", "2"}),
      Row("lobes1", "c", 2, 31, 5, 90, {"32", "64", "64", "1", "1", "2"}),
      Row("res8-ss8", "c", 2, 29, 1, 10, {"8", "64", "64", "2", "1", "8"}),
      // Not single precompute variations: left out.
      Row("small", "a", 64, 18, 1, 10, {"16", "36", "36", "1", "1", "4"}),
      Row("level-none", "a", 64, 15, 10, 100, kDefault, "NONE"),
      Row("ss4", "a", 64, 15, 10, 100, {"32", "64", "64", "2", "1", "4"}),
  });
  const std::vector<MeasuredVariation> variations = DistillSweep(table);
  ASSERT_EQ(variations.size(), 3u);
  EXPECT_EQ(variations[0].configuration, "lobes1");
  EXPECT_EQ(variations[0].footprint, FootprintClass::kNear);
  EXPECT_EQ(variations[0].lobes, 1u);
  EXPECT_EQ(variations[0].spatial_resolution, 0u);
  EXPECT_EQ(variations[0].scenes, 2);
  EXPECT_NEAR(variations[0].psnr_change_db, -0.5, 1e-9);
  EXPECT_NEAR(variations[0].precompute_ratio, 0.5, 1e-9);
  EXPECT_NEAR(variations[0].bytes_ratio, 0.9, 1e-9);
  EXPECT_EQ(variations[1].footprint, FootprintClass::kFar);
  EXPECT_NEAR(variations[1].psnr_change_db, 1.0, 1e-9);
  EXPECT_EQ(variations[2].configuration, "res8-ss8");
  EXPECT_EQ(variations[2].spatial_resolution, 8u);
  EXPECT_EQ(variations[2].supersampling, 8u);
  EXPECT_NEAR(variations[2].precompute_ratio, 0.1, 1e-9);
  EXPECT_NE(VariationsAsCpp(variations).find(
                "{\"res8-ss8\", FootprintClass::kFar, FabricKind::kKnitMatte, 8, 0, 0, -1, 8, -1.000, -1.000"),
            std::string::npos);
}

TEST(SweepDistill, KeepsEachFabricKindApartWithItsWorstSceneAndSkipsNaNImages) {
  const CsvTable table = Table({
      Row("default", "knit.a", 64, 20, 10, 100, kDefault),
      Row("default", "knit.b", 60, 22, 10, 100, kDefault),
      Row("default", "knit.c", 50, 21, 10, 100, kDefault),
      Row("default", "satin.a", 64, 20, 20, 100, kDefault, "TRILINEAR", "woven-glossy"),
      Row("lobes1", "knit.a", 64, 21, 5, 90, kLobes1),
      Row("lobes1", "knit.b", 60, 20.5, 5, 90, kLobes1),
      Row("lobes1", "knit.c", 50, NAN, 5, 90, kLobes1),  // a NaN image: no figure
      Row("lobes1", "satin.a", 64, 18, 5, 90, kLobes1, "TRILINEAR", "woven-glossy"),
  });
  const std::vector<MeasuredVariation> variations = DistillSweep(table);
  ASSERT_EQ(variations.size(), 2u);
  EXPECT_EQ(variations[0].fabric_kind, FabricKind::kKnitMatte);
  EXPECT_EQ(variations[0].scenes, 2);
  EXPECT_NEAR(variations[0].psnr_change_db, -0.25, 1e-9);
  EXPECT_NEAR(variations[0].worst_psnr_change_db, -1.5, 1e-9);
  EXPECT_EQ(variations[1].fabric_kind, FabricKind::kWovenGlossy);
  EXPECT_NEAR(variations[1].worst_psnr_change_db, -2.0, 1e-9);
  EXPECT_NEAR(variations[1].precompute_ratio, 0.25, 1e-9);
}

TEST(SweepDistill, GivesAClassOnlyWhereTheVariationRanOnAllOfIt) {
  const CsvTable table = Table({
      Row("default", "knit.a", 64, 20, 10, 100, kDefault),
      Row("default", "knit.b", 60, 22, 10, 100, kDefault),
      Row("default", "knit.c", 2, 21, 10, 100, kDefault),
      Row("lobes1", "knit.a", 64, 21, 5, 90, kLobes1),  // near: a but not b
      Row("lobes1", "knit.c", 2, 21, 5, 90, kLobes1),   // far: all of it
  });
  const std::vector<MeasuredVariation> variations = DistillSweep(table);
  ASSERT_EQ(variations.size(), 1u);
  EXPECT_EQ(variations[0].footprint, FootprintClass::kFar);
}

TEST(SweepDistill, RejectsAnUnknownFabricKindNamingIt) {
  try {
    DistillSweep(Table({Row("default", "a", 64, 20, 10, 100, kDefault, "TRILINEAR", "silk")}));
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("fabric_kind 'silk'"), std::string::npos);
  }
}

TEST(SweepDistill, NeedsTheBaseline) {
  EXPECT_THROW(DistillSweep(Table({Row("lobes1", "a", 64, 19, 5, 90, kDefault)})), Error);
}

}  // namespace
}  // namespace loom::lab
