#include "lab/sweep_distill.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <tuple>

#include "core/util/error.h"
#include "core/util/file_io.h"

namespace loom::lab {
namespace {

// A sweep CSV with the columns DistillSweep reads.
CsvTable Table(std::vector<std::vector<std::string>> rows) {
  CsvTable table;
  table.columns = {"configuration", "scene",         "method",        "footprint_pixels", "fabric_kind", "psnr_db",
                   "precompute_cpu_seconds", "asset_bytes", "spatial_resolution", "view_directions",
                   "light_directions",   "lobes",       "lookup_table",  "supersampling",    "level_mode",
                   "texel_filter",       "msaa_samples",       "lod_bias",  "seed"};
  table.rows = std::move(rows);
  return table;
}

// One svbrdf row: `settings` = resolution, views, lights, lobes, LUT, supersampling;
// rendered with the default render settings unless `level` or `filter` say otherwise.
std::vector<std::string> Row(const std::string& configuration, const std::string& scene, double footprint,
                             double psnr, double seconds, double bytes, std::vector<std::string> settings,
                             const std::string& level = "TRILINEAR", const std::string& kind = "knit-matte",
                             const std::string& seed = "0", const std::string& filter = "BILINEAR") {
  std::vector<std::string> row = {configuration, scene, "svbrdf", std::to_string(footprint), kind, std::to_string(psnr),
                                  std::to_string(seconds), std::to_string(bytes)};
  row.insert(row.end(), settings.begin(), settings.end());
  row.push_back(level);
  row.push_back(filter);
  row.push_back("4");
  row.push_back("0");
  row.push_back(seed);
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

// A row of another fabric method: `own` its method_settings column.
// A row of a sweep with the method_settings and sampling_plane columns (the table
// methods' default plane is view-depth, svbrdf's the top face).
std::vector<std::string> MethodRow(const std::string& configuration, const std::string& scene, double footprint,
                                   double psnr, double seconds, double bytes, const std::string& method,
                                   const std::string& own, std::vector<std::string> settings,
                                   const std::string& plane = "view-depth") {
  std::vector<std::string> row = Row(configuration, scene, footprint, psnr, seconds, bytes, std::move(settings));
  row[2] = method;
  row.push_back(own);
  row.push_back(plane);
  return row;
}

TEST(SweepDistill, TakesAnotherMethodAtItsDefaultsAsAVariationAndNoOtherConfigurationOfIt) {
  CsvTable table = Table({});
  table.columns.push_back("method_settings");
  table.columns.push_back("sampling_plane");
  const auto base = [](const std::string& scene, double footprint, double psnr) {
    return MethodRow("default", scene, footprint, psnr, 10, 100, "svbrdf", "", kDefault, "top");
  };
  const std::vector<std::string> table81 = {"32", "81", "64", "2", "1", "2"};
  table.rows = {
      base("a", 64, 20),
      base("b", 60, 22),
      MethodRow("factored", "a", 64, 21, 1, 700, "factored", R"({"rank":4})", table81),
      MethodRow("factored", "b", 60, 21.5, 1, 700, "factored", R"({"rank":4})", table81),
      // Not the method's defaults: its own settings, or the shared ones, differ.
      MethodRow("factored-rank8", "a", 64, 23, 1, 1400, "factored", R"({"rank":8})", table81),
      MethodRow("factored-rank8", "b", 60, 23, 1, 1400, "factored", R"({"rank":8})", table81),
      MethodRow("factored-views64", "a", 64, 21, 1, 600, "factored", R"({"rank":4})", kDefault),
      MethodRow("factored-views64", "b", 60, 21, 1, 600, "factored", R"({"rank":4})", kDefault),
      MethodRow("factored-top", "a", 64, 21, 1, 700, "factored", R"({"rank":4})", table81, "top"),
      MethodRow("factored-top", "b", 60, 21, 1, 700, "factored", R"({"rank":4})", table81, "top"),
      // svbrdf on another sampling plane: not a setting the planner varies.
      MethodRow("viewdepth", "a", 64, 22, 10, 100, "svbrdf", "", kDefault),
      MethodRow("viewdepth", "b", 60, 23, 10, 100, "svbrdf", "", kDefault),
  };
  const std::vector<MeasuredVariation> variations = DistillSweep(table);
  ASSERT_EQ(variations.size(), 1u);
  const MeasuredVariation& factored = variations[0];
  EXPECT_EQ(factored.configuration, "factored");
  EXPECT_EQ(factored.method, v1::FABRIC_METHOD_FACTORED);
  EXPECT_EQ(factored.directions, 0u);  // the method's own view grid, not a settings change
  EXPECT_NEAR(factored.psnr_change_db, 0.25, 1e-9);
  EXPECT_NEAR(factored.worst_psnr_change_db, -0.5, 1e-9);
  EXPECT_NEAR(factored.precompute_ratio, 0.1, 1e-9);
  EXPECT_NEAR(factored.bytes_ratio, 7.0, 1e-9);
  EXPECT_NE(VariationsAsCpp(variations).find("2, v1::FABRIC_METHOD_FACTORED}"), std::string::npos);
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

TEST(SweepDistill, TakesRepeatsUnderOtherSeedsAsOneFigureTheirMean) {
  const CsvTable table = Table({
      Row("default", "knit.a", 2, 20, 10, 100, kDefault),
      Row("default", "knit.b", 2, 24, 10, 100, kDefault),
      Row("lobes1", "knit.a", 2, 19, 5, 90, kLobes1),
      Row("lobes1", "knit.b", 2, 21, 5, 90, kLobes1),
      // The same settings under another seed, and a seed measured twice:
      Row("seed2", "knit.a", 2, 22, 12, 100, kDefault, "TRILINEAR", "knit-matte", "2"),
      Row("lobes1-seed2", "knit.a", 2, 20, 7, 90, kLobes1, "TRILINEAR", "knit-matte", "2"),
      Row("default-again", "knit.a", 2, 20, 10, 100, kDefault),
  });
  const std::vector<MeasuredVariation> variations = DistillSweep(table);
  ASSERT_EQ(variations.size(), 1u);  // the repeats are no variations of their own
  EXPECT_EQ(variations[0].configuration, "lobes1");
  // knit.a: (19 + 20)/2 − (20 + 22)/2 = −1.5; knit.b: 21 − 24 = −3.
  EXPECT_NEAR(variations[0].psnr_change_db, -2.25, 1e-9);
  EXPECT_NEAR(variations[0].worst_psnr_change_db, -3.0, 1e-9);
  // (6 + 5) / (11 + 10) over the two scenes.
  EXPECT_NEAR(variations[0].precompute_ratio, 11.0 / 21.0, 1e-9);
}

TEST(SweepDistill, ReadsASweepWithItsRepeatsFromSeveralFiles) {
  const std::filesystem::path dir = std::filesystem::path(::testing::TempDir()) / "distill_csvs";
  std::filesystem::create_directories(dir);
  const CsvTable first = Table({Row("default", "knit.a", 2, 20, 10, 100, kDefault),
                                Row("lobes1", "knit.a", 2, 19, 5, 90, kLobes1)});
  CsvTable second = Table({Row("seed2", "knit.a", 2, 22, 10, 100, kDefault, "TRILINEAR", "knit-matte", "2")});
  auto write = [&](const CsvTable& table, const std::string& name) {
    std::string text = CsvLine(table.columns);
    for (const auto& row : table.rows) text += CsvLine(row);
    WriteFileAtomic(dir / name, text);
  };
  write(first, "sweep.csv");
  write(second, "seeds.csv");
  const std::vector<MeasuredVariation> variations = DistillSweep(ReadCsvs({dir / "sweep.csv", dir / "seeds.csv"}));
  ASSERT_EQ(variations.size(), 1u);
  EXPECT_NEAR(variations[0].psnr_change_db, -2.0, 1e-9);

  second.columns.back() = "ray_seed";
  write(second, "other.csv");
  try {
    ReadCsvs({dir / "sweep.csv", dir / "other.csv"});
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("other.csv: its columns differ from"), std::string::npos);
  }
}

TEST(SweepDistill, RejectsAnUnknownFabricKindNamingIt) {
  try {
    DistillSweep(Table({Row("default", "a", 64, 20, 10, 100, kDefault, "TRILINEAR", "silk")}));
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("fabric_kind 'silk'"), std::string::npos);
  }
}

// So is one whose baseline was acquired on another sampling plane than the default's.
TEST(SweepDistill, RefusesABaselineNotAcquiredOnTheDefaultSamplingPlane) {
  CsvTable table = Table({});
  table.columns.push_back("method_settings");
  table.columns.push_back("sampling_plane");
  table.rows = {MethodRow("default", "a", 64, 20, 10, 100, "svbrdf", "", kDefault, "top"),
                MethodRow("lobes1", "a", 64, 19, 5, 90, "svbrdf", "", kLobes1, "top")};
  EXPECT_NO_THROW(DistillSweep(table));
  table.rows[0].back() = "view-depth";
  table.rows[1].back() = "view-depth";
  try {
    DistillSweep(table);
    FAIL() << "a view-depth baseline was distilled";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("sampling plane view-depth, but the default is top"), std::string::npos)
        << e.what();
  }
}

// Sweeps from before the shading_rate column shaded once per pixel; a baseline
// shaded per sample is not the default render.
TEST(SweepDistill, RefusesABaselineShadedPerSample) {
  CsvTable table = Table({Row("default", "a", 64, 20, 10, 100, kDefault), Row("lobes1", "a", 64, 19, 5, 90, kLobes1)});
  EXPECT_NO_THROW(DistillSweep(table));
  table.columns.push_back("shading_rate");
  for (auto& row : table.rows) row.push_back("PIXEL");
  EXPECT_EQ(DistillSweep(table).size(), 1u);
  for (auto& row : table.rows) row.back() = "SAMPLE";
  try {
    DistillSweep(table);
    FAIL() << "a baseline shaded per sample was distilled";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("shading_rate SAMPLE"), std::string::npos) << e.what();
  }
}

TEST(SweepDistill, NeedsTheBaseline) {
  EXPECT_THROW(DistillSweep(Table({Row("lobes1", "a", 64, 19, 5, 90, kDefault)})), Error);
}

// The planner applies the figures to the default render: a sweep whose baseline
// was rendered otherwise (measured before the defaults changed) is refused, naming
// what differs, rather than distilled into figures of another renderer.
TEST(SweepDistill, RefusesABaselineNotRenderedWithTheDefaultRenderSettings) {
  const auto distill = [](const std::string& level, const std::string& filter) {
    DistillSweep(Table({Row("default", "a", 64, 20, 10, 100, kDefault, level, "knit-matte", "0", filter),
                        Row("lobes1", "a", 64, 19, 5, 90, kLobes1, level, "knit-matte", "0", filter)}));
  };
  EXPECT_NO_THROW(distill("TRILINEAR", "BILINEAR"));
  for (const auto& [level, filter, named] : {std::tuple{"TRILINEAR", "NEAREST", "texel_filter NEAREST"},
                                             std::tuple{"NONE", "BILINEAR", "level_mode NONE"}}) {
    try {
      distill(level, filter);
      FAIL() << named;
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument);
      EXPECT_NE(std::string(e.what()).find(named), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("the default render is level_mode TRILINEAR, texel_filter BILINEAR"),
                std::string::npos)
          << e.what();
    }
  }
}

}  // namespace
}  // namespace loom::lab
