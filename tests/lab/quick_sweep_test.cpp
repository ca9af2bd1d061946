// The CI sweep end to end: `loom-lab sweep bench/sweep_quick.json`, then `loom-lab
// chart` on its CSV. Asserts the rows, their figures, the chart files and the
// Pareto front; a second sweep into the same directory measures nothing (resume).

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <map>
#include <nlohmann/json.hpp>

#include "core/util/file_io.h"
#include "lab/csv_table.h"

namespace loom::lab {
namespace {

// Runs loom-lab with `arguments`; returns its stdout, fails the test on a non-zero exit.
std::string RunLab(const std::string& arguments, const std::filesystem::path& out) {
  const std::filesystem::path stdout_file = out / "stdout.txt";
  const std::string command =
      std::string("\"") + LOOM_LAB_BINARY + "\" " + arguments + " > \"" + stdout_file.string() + "\"";
  const int status = std::system(command.c_str());
  EXPECT_EQ(status, 0) << command;
  return ReadFile(stdout_file);
}

double Figure(const CsvTable& table, const std::vector<std::string>& row, const std::string& column) {
  const std::string& field = row[table.Column(column)];
  EXPECT_FALSE(field.empty()) << column;
  return field.empty() ? NAN : std::stod(field);
}

TEST(QuickSweep, MeasuresEveryRowAndChartsAParetoFront) {
  const std::filesystem::path out =
      std::filesystem::temp_directory_path() / ("loom_quick_sweep_" + std::to_string(::getpid()));
  std::filesystem::remove_all(out);
  std::filesystem::create_directories(out);
  const std::string grid = (std::filesystem::path(LOOM_SOURCE_DIR) / "bench/sweep_quick.json").string();

  const auto sweep = nlohmann::json::parse(RunLab("--json sweep \"" + grid + "\" --software --out \"" +
                                                  (out / "results").string() + "\"", out));
  EXPECT_EQ(sweep.at("measured"), 10);  // 5 configurations × 2 scenes

  const CsvTable table = ReadCsv(out / "results/sweep_quick.csv");
  ASSERT_EQ(table.rows.size(), 10u);
  int svbrdf_rows = 0;
  for (const auto& row : table.rows) {
    SCOPED_TRACE(row[0] + " " + row[1]);
    for (const char* column : {"frame_ms", "rmse", "psnr_db", "perceptual_error", "flicker"}) {
      EXPECT_TRUE(std::isfinite(Figure(table, row, column))) << column;
    }
    EXPECT_GT(Figure(table, row, "frame_ms"), 0.0);
    EXPECT_GT(Figure(table, row, "rmse"), 0.0);  // nothing matches the ground truth exactly
    EXPECT_GE(Figure(table, row, "perceptual_error"), 0.0);
    EXPECT_LE(Figure(table, row, "perceptual_error"), 2.0);
    // The kind the planner's measurements are kept by (core/plan/fabric_kind.h).
    EXPECT_EQ(row[table.Column("fabric_kind")], row[1].starts_with("plain.") ? "woven-matte" : "knit-matte");
    if (row[table.Column("method")] == "svbrdf") {
      ++svbrdf_rows;
      EXPECT_GT(Figure(table, row, "precompute_seconds"), 0.0);
      EXPECT_GT(Figure(table, row, "precompute_cpu_seconds"), 0.0);
      EXPECT_GT(Figure(table, row, "asset_bytes"), 0.0);
      EXPECT_TRUE(std::isfinite(Figure(table, row, "gpu_ms")));
    }
  }
  EXPECT_EQ(svbrdf_rows, 6);
  for (const char* scene : {"stockinette.flat0.near", "plain.flat60.far"}) {
    EXPECT_TRUE(std::filesystem::exists(out / "results/ground_truth" / (std::string(scene) + ".exr"))) << scene;
  }

  // The reference gets closer to the ground truth with more samples.
  std::map<std::string, double> psnr;
  for (const auto& row : table.rows) psnr[row[0] + "@" + row[1]] = Figure(table, row, "psnr_db");
  EXPECT_GT(psnr.at("reference-4@plain.flat60.far"), psnr.at("reference-1@plain.flat60.far"));

  // Resume: every row is there, so nothing is measured again.
  const auto again = nlohmann::json::parse(RunLab("--json sweep \"" + grid + "\" --software --out \"" +
                                                  (out / "results").string() + "\"", out));
  EXPECT_EQ(again.at("measured"), 0);
  EXPECT_EQ(ReadCsv(out / "results/sweep_quick.csv").rows.size(), 10u);

  const auto chart = nlohmann::json::parse(
      RunLab("--json chart \"" + (out / "results/sweep_quick.csv").string() + "\" --out \"" +
                 (out / "chart").string() + "\"",
             out));
  EXPECT_EQ(chart.at("points"), 5);
  for (const auto& file : chart.at("files")) {
    const std::string path = file.get<std::string>();
    const std::string bytes = ReadFile(path);
    ASSERT_GT(bytes.size(), 1000u) << path;
    if (path.ends_with(".png")) {
      EXPECT_EQ(bytes.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8)) << path;
    } else {
      EXPECT_NE(bytes.find("<svg"), std::string::npos) << path;
      EXPECT_NE(bytes.find("</svg>"), std::string::npos) << path;
    }
  }
  for (const char* axis : {"frame_time", "precompute_time"}) {
    for (const char* metric : {"psnr", "perceptual"}) {
      const auto& front = chart.at("pareto").at(axis).at(metric);
      EXPECT_FALSE(front.empty()) << axis << " " << metric;
      // Along the front, more cost buys less error.
      for (size_t i = 1; i < front.size(); ++i) {
        EXPECT_GT(front[i].at(axis).get<double>(), front[i - 1].at(axis).get<double>());
      }
    }
  }
  EXPECT_EQ(nlohmann::json::parse(ReadFile(out / "chart/pareto.json")), chart.at("pareto"));
  std::filesystem::remove_all(out);
}

}  // namespace
}  // namespace loom::lab
