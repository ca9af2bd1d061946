#pragma once
// The sweep's results file: one CSV row per (configuration, scene), appended and
// flushed as each is measured, so an interrupted sweep resumes where it stopped:
// Open reads the rows already there and Contains says which to skip. A line cut off
// by a crash is dropped (the file is truncated to its last complete row) and that
// row is measured again.

#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "loom/v1/scene.pb.h"

namespace loom::lab {

// A GPU row's render columns (level_mode, texel_filter, msaa_samples, lod_bias,
// shading_rate): the enums' names without their prefixes and the numbers, as the
// sweep writes them and the planner's distill checks them. Sweeps from before the
// shading_rate column shaded once per pixel.
struct RenderColumns {
  std::string level_mode, texel_filter, msaa_samples, lod_bias, shading_rate;
  bool operator==(const RenderColumns&) const = default;
};
RenderColumns SweepRenderColumns(const v1::RenderSettings& render);

// A row's sampling_plane column: "top" or "view-depth" (PrecomputeSettings.sampling_plane,
// defaults applied). Sweeps from before the column had every view's texels on the top face.
std::string SamplingPlaneColumn(v1::SamplingPlane plane);
inline constexpr const char* kSamplingPlaneBeforeTheColumn = "top";
inline constexpr const char* kShadingRateBeforeTheColumn = "PIXEL";

class SweepResults {
 public:
  // `columns` must start with "configuration" and "scene", the row's key. An
  // existing file with other columns is Error(kFailedPrecondition) (a sweep of
  // another version: use a new output directory).
  SweepResults(std::filesystem::path path, std::vector<std::string> columns);

  bool Contains(const std::string& configuration, const std::string& scene) const;
  size_t size() const { return done_.size(); }

  // `fields` in column order; written and flushed at once.
  void Append(const std::vector<std::string>& fields);

 private:
  std::filesystem::path path_;
  std::vector<std::string> columns_;
  std::set<std::pair<std::string, std::string>> done_;
  std::ofstream out_;
};

}  // namespace loom::lab
