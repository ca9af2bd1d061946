#include "lab/sweep_results.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstring>

#include "core/util/error.h"
#include "core/util/file_io.h"
#include "lab/csv_table.h"

namespace loom::lab {

namespace {

// Shortest exact text: "0", "-0.5".
std::string FormatLodBias(float bias) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", static_cast<double>(bias));
  return text;
}

}  // namespace

RenderColumns SweepRenderColumns(const v1::RenderSettings& render) {
  return {v1::LevelMode_Name(render.level_mode()).substr(std::strlen("LEVEL_MODE_")),
          v1::TexelFilter_Name(render.texel_filter()).substr(std::strlen("TEXEL_FILTER_")),
          std::to_string(render.msaa_samples()), FormatLodBias(render.lod_bias()),
          v1::ShadingRate_Name(render.shading_rate()).substr(std::strlen("SHADING_RATE_"))};
}

std::string SamplingPlaneColumn(v1::SamplingPlane plane) {
  std::string name = v1::SamplingPlane_Name(plane).substr(std::strlen("SAMPLING_PLANE_"));
  std::transform(name.begin(), name.end(), name.begin(), [](char c) { return c == '_' ? '-' : static_cast<char>(std::tolower(c)); });
  return name;
}

SweepResults::SweepResults(std::filesystem::path path, std::vector<std::string> columns)
    : path_(std::move(path)), columns_(std::move(columns)) {
  if (columns_.size() < 2 || columns_[0] != "configuration" || columns_[1] != "scene") {
    throw Error(ErrorCode::kInternal, "sweep columns must start with configuration, scene");
  }
  if (!path_.parent_path().empty()) std::filesystem::create_directories(path_.parent_path());
  bool fresh = true;
  if (std::filesystem::exists(path_)) {
    const std::string text = ReadFile(path_);
    size_t complete = 0;
    const CsvTable table = ParseCsv(text, &complete);
    if (!table.columns.empty()) {
      if (table.columns != columns_) {
        throw Error(ErrorCode::kFailedPrecondition,
                    path_.string() + ": its columns differ from this sweep's; resume only into a CSV this "
                                     "version wrote (use another --out)");
      }
      for (const auto& row : table.rows) done_.emplace(row[0], row[1]);
      fresh = false;
    }
    if (complete < text.size()) std::filesystem::resize_file(path_, complete);
  }
  out_.open(path_, std::ios::app | std::ios::binary);
  if (!out_) throw Error(ErrorCode::kNotFound, path_.string() + ": cannot open for writing");
  if (fresh) {
    std::filesystem::resize_file(path_, 0);
    out_ << CsvLine(columns_);
    out_.flush();
  }
}

bool SweepResults::Contains(const std::string& configuration, const std::string& scene) const {
  return done_.contains({configuration, scene});
}

void SweepResults::Append(const std::vector<std::string>& fields) {
  if (fields.size() != columns_.size()) {
    throw Error(ErrorCode::kInternal, "sweep row has " + std::to_string(fields.size()) + " fields, expected " +
                                          std::to_string(columns_.size()));
  }
  out_ << CsvLine(fields);
  out_.flush();
  if (!out_) throw Error(ErrorCode::kInternal, path_.string() + ": write failed");
  done_.emplace(fields[0], fields[1]);
}

}  // namespace loom::lab
