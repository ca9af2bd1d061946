// loom-lab chart: a sweep CSV (loom-lab sweep) as speed-versus-accuracy charts.
// Each configuration becomes one point: the median of its figures over the scenes
// it was measured on (so compare configurations measured on the same scenes;
// --scenes narrows the rows). Two charts, each as PNG and SVG, drawn by gnuplot:
//
//   error_vs_frame_time       PSNR and 1 − SSIM against frame milliseconds, every method
//   error_vs_precompute_time  the same against precompute seconds (svbrdf: the
//                             reference precomputes nothing)
//
// One series per method; the Pareto front of each panel (no other point is both
// faster and more accurate) is drawn as a line through circled points, and listed
// in pareto.json and on stdout, so scripts and tests can read it.

#include <fnmatch.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>

#include "core/util/error.h"
#include "core/util/file_io.h"
#include "core/util/subprocess.h"
#include "lab/csv_table.h"
#include "lab/lab_command.h"
#include "lab/pareto_front.h"

namespace loom::lab {
namespace {

struct ChartPoint {
  std::string configuration, method;
  double frame_ms = 0, precompute_seconds = 0, psnr_db = 0, perceptual_error = 0;
  int rows = 0;
};

double Parse(const std::string& field) {
  if (field.empty()) return NAN;
  try {
    return std::stod(field);
  } catch (const std::exception&) {
    return NAN;
  }
}

double Median(std::vector<double> values) {
  if (values.empty()) return NAN;
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

// The median of each figure per configuration over the rows whose scene matches
// one of `globs` (all rows when empty), in order of first appearance. The median, not the mean: a setting that
// blows up on one scene (a fit extrapolating to 10^20) would otherwise move its
// point off the chart; such rows are counted in `rows` and listed by the sweep's
// CSV. Non-finite figures are left out.
std::vector<ChartPoint> Aggregate(const CsvTable& table, const std::vector<std::string>& globs) {
  const size_t configuration = table.Column("configuration"), scene = table.Column("scene"),
               method = table.Column("method"), frame = table.Column("frame_ms"),
               precompute = table.Column("precompute_seconds"), psnr = table.Column("psnr_db"),
               perceptual = table.Column("perceptual_error");
  std::vector<ChartPoint> points;
  std::map<std::string, size_t> index;
  std::vector<std::array<std::vector<double>, 4>> figures;
  for (const auto& row : table.rows) {
    const bool wanted = globs.empty() || std::any_of(globs.begin(), globs.end(), [&](const std::string& glob) {
                          return fnmatch(glob.c_str(), row[scene].c_str(), 0) == 0;
                        });
    if (!wanted) continue;
    auto [found, added] = index.emplace(row[configuration], points.size());
    if (added) {
      points.push_back({row[configuration], row[method]});
      figures.emplace_back();
    }
    ++points[found->second].rows;
    const double values[4] = {Parse(row[frame]), Parse(row[precompute]), Parse(row[psnr]), Parse(row[perceptual])};
    for (int i = 0; i < 4; ++i) {
      if (std::isfinite(values[i])) figures[found->second][i].push_back(values[i]);
    }
  }
  for (size_t i = 0; i < points.size(); ++i) {
    points[i].frame_ms = Median(figures[i][0]);
    points[i].precompute_seconds = Median(figures[i][1]);
    points[i].psnr_db = Median(figures[i][2]);
    points[i].perceptual_error = Median(figures[i][3]);
  }
  return points;
}

struct Axis {
  std::string name, title, label;
  double ChartPoint::*value;
  bool svbrdf_only;  // the reference has no such cost
};
struct Metric {
  std::string name, label;
  double ChartPoint::*value;
  bool higher_is_better;
};

const Axis kAxes[] = {{"frame_time", "frame time", "frame time (ms, CPU wall, median over scenes, log scale)", &ChartPoint::frame_ms, false},
                      {"precompute_time", "precompute time", "precompute time (s, log scale)", &ChartPoint::precompute_seconds, true}};
const Metric kMetrics[] = {{"psnr", "PSNR against the ground truth (dB, median over scenes)", &ChartPoint::psnr_db, true},
                           {"perceptual", "perceptual error 1 - SSIM (median over scenes)", &ChartPoint::perceptual_error, false}};

std::string GnuplotString(const std::string& text) {
  std::string quoted = "\"";
  for (const char c : text) quoted += c == '"' || c == '\\' ? std::string("\\") + c : std::string(1, c);
  return quoted + "\"";
}

}  // namespace

LabCommand AddChartCommand(CLI::App& app, const LabFlags& flags) {
  struct Options {
    std::string csv, out, title;
    std::vector<std::string> scenes;
  };
  auto options = std::make_shared<Options>();
  auto* command = app.add_subcommand(
      "chart", "Draw a sweep CSV as error against frame time and against precompute time (PNG and SVG, "
               "Pareto front marked; needs gnuplot)");
  command->add_option("csv", options->csv, "Sweep results (loom-lab sweep)")->required();
  command->add_option("--out,-o", options->out, "Output directory")->required();
  command->add_option("--scenes", options->scenes, "Only rows whose scene matches one of these globs");
  command->add_option("--title", options->title, "Chart title (default: the CSV's name)");
  return {command, [&flags, options] {
            const std::string gnuplot_hint = "install the Debian package gnuplot-nox (scripts/setup.sh)";
            if (FindOnPath("gnuplot").empty()) {  // before any work
              throw Error(ErrorCode::kUnavailable, "gnuplot not found on PATH: " + gnuplot_hint);
            }
            const std::vector<ChartPoint> points = Aggregate(ReadCsv(options->csv), options->scenes);
            if (points.empty()) throw Error(ErrorCode::kInvalidArgument, options->csv + ": no rows to chart");
            const std::filesystem::path out = options->out;
            std::filesystem::create_directories(out);
            const std::string title =
                options->title.empty() ? std::filesystem::path(options->csv).filename().string() : options->title;

            // Data: one block per method, then one file per panel's front.
            std::string data = "# configuration method frame_ms precompute_seconds psnr_db perceptual_error rows\n";
            std::vector<std::string> methods;
            for (const ChartPoint& p : points) {
              if (std::find(methods.begin(), methods.end(), p.method) == methods.end()) methods.push_back(p.method);
            }
            for (const std::string& method : methods) {
              data += "# method " + method + "\n";
              for (const ChartPoint& p : points) {
                if (p.method != method) continue;
                char line[512];
                std::snprintf(line, sizeof line, "%s %s %.6g %.6g %.6g %.6g %d\n", GnuplotString(p.configuration).c_str(),
                              p.method.c_str(), p.frame_ms, p.precompute_seconds, p.psnr_db, p.perceptual_error, p.rows);
                data += line;
              }
              data += "\n\n";
            }
            WriteFileAtomic(out / "points.dat", data);

            nlohmann::json fronts;
            std::string script;
            for (const Axis& axis : kAxes) {
              for (const Metric& metric : kMetrics) {
                std::vector<CostError> cost_error;
                for (const ChartPoint& p : points) {
                  const bool counted = !axis.svbrdf_only || p.method == "svbrdf";
                  const double y = p.*metric.value;
                  cost_error.push_back({counted ? p.*axis.value : NAN, metric.higher_is_better ? -y : y});
                }
                std::string front_data;
                nlohmann::json front = nlohmann::json::array();
                for (const size_t i : ParetoFront(cost_error)) {
                  const ChartPoint& p = points[i];
                  front.push_back({{"configuration", p.configuration}, {"method", p.method},
                                   {axis.name, p.*axis.value}, {metric.name, p.*metric.value}});
                  char line[256];
                  std::snprintf(line, sizeof line, "%.6g %.6g\n", p.*axis.value, p.*metric.value);
                  front_data += line;
                }
                const std::string front_file = "front_" + axis.name + "_" + metric.name + ".dat";
                WriteFileAtomic(out / front_file, front_data);
                fronts[axis.name][metric.name] = front;
              }
            }

            // One script draws both charts in both formats.
            const auto chart = [&](const Axis& axis, int column) {
              std::string s = "set multiplot layout 1,2 title " + GnuplotString(title + ": error against " + axis.title) + "\n";
              for (const Metric& metric : kMetrics) {
                const int y_column = metric.name == "psnr" ? 5 : 6;
                s += "set xlabel " + GnuplotString(axis.label) + "\nset ylabel " + GnuplotString(metric.label) + "\n";
                // The corner away from the front: cheap and inaccurate is where no point lies.
                s += metric.higher_is_better ? "set key top left\n" : "set key bottom left\n";
                s += "plot ";
                for (size_t m = 0; m < methods.size(); ++m) {
                  if (axis.svbrdf_only && methods[m] != "svbrdf") continue;
                  s += "'points.dat' index " + std::to_string(m) + " using " + std::to_string(column) + ":" +
                       std::to_string(y_column) + " with points pt " + std::to_string(m == 0 ? 7 : 5) +
                       " ps 0.8 title " + GnuplotString(methods[m]) + ", ";
                  s += "'' index " + std::to_string(m) + " using " + std::to_string(column) + ":" +
                       std::to_string(y_column) + ":1 with labels font ',7' offset 0.5,0.5 left notitle, ";
                }
                s += "'front_" + axis.name + "_" + metric.name +
                     ".dat' using 1:2 with linespoints lw 1.5 pt 6 ps 2 lc rgb 'black' title 'Pareto front'\n";
              }
              return s + "unset multiplot\n";
            };
            script = "cd " + GnuplotString(std::filesystem::absolute(out).string()) +
                     "\nset datafile missing 'nan'\nset logscale x\nset grid\n";
            for (size_t a = 0; a < std::size(kAxes); ++a) {
              const int column = a == 0 ? 3 : 4;
              const std::string stem = "error_vs_" + kAxes[a].name;
              script += "set terminal pngcairo noenhanced size 1400,600 font ',10'\nset output '" + stem + ".png'\n" +
                        chart(kAxes[a], column) + "set output\n";
              script += "set terminal svg noenhanced size 1400,600 font ',10' background '#ffffff'\nset output '" + stem +
                        ".svg'\n" + chart(kAxes[a], column) + "set output\n";
            }
            WriteFileAtomic(out / "chart.gp", script);
            RunProgram("gnuplot", {(out / "chart.gp").string()}, gnuplot_hint);
            WriteFileAtomic(out / "pareto.json", fronts.dump(2) + "\n");

            nlohmann::json files = nlohmann::json::array();
            for (const Axis& axis : kAxes) {
              for (const char* extension : {".png", ".svg"}) {
                files.push_back((out / ("error_vs_" + axis.name + extension)).string());
              }
            }
            if (flags.json) {
              PrintJson({{"points", points.size()}, {"files", files}, {"pareto", fronts}});
            } else {
              for (const auto& file : files) std::printf("wrote %s\n", file.get<std::string>().c_str());
              for (const Axis& axis : kAxes) {
                for (const Metric& metric : kMetrics) {
                  std::printf("Pareto front, %s against %s:", metric.name.c_str(), axis.name.c_str());
                  for (const auto& p : fronts[axis.name][metric.name]) {
                    std::printf(" %s", p["configuration"].get<std::string>().c_str());
                  }
                  std::printf("\n");
                }
              }
            }
            return 0;
          }};
}

}  // namespace loom::lab
