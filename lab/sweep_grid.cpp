#include "lab/sweep_grid.h"

#include <fnmatch.h>

#include <nlohmann/json.hpp>
#include <set>

#include "core/methods/fabric_method.h"
#include "core/plan/precompute_plan.h"
#include "core/scene/scene_geometry.h"
#include "core/spec/defaults.h"
#include "core/spec/spec_json.h"
#include "core/spec/validate.h"
#include "core/util/error.h"
#include "core/util/file_io.h"

namespace loom::lab {
namespace {

using nlohmann::json;

bool Matches(const std::vector<std::string>& patterns, const std::string& name) {
  for (const std::string& pattern : patterns) {
    if (fnmatch(pattern.c_str(), name.c_str(), 0) == 0) return true;
  }
  return false;
}

std::vector<std::string> Patterns(const json& object, const std::string& field) {
  std::vector<std::string> patterns;
  if (!object.contains("scenes")) return patterns;
  if (!object.at("scenes").is_array() || object.at("scenes").empty()) {
    throw Error(ErrorCode::kInvalidArgument, field + ": a non-empty list of scene-name globs");
  }
  for (const json& pattern : object.at("scenes")) patterns.push_back(pattern.get<std::string>());
  return patterns;
}

template <typename Settings>
Settings Merged(const Settings& base, const json& object, const std::string& key, const std::string& root) {
  Settings merged = base;
  if (object.contains(key)) merged.MergeFrom(ParseSpecJson<Settings>(object.at(key).dump(), root));
  return merged;
}

}  // namespace

bool SweepGrid::Applies(const SweepConfiguration& configuration, const BenchScene& scene) const {
  return configuration.scene_patterns.empty() || Matches(configuration.scene_patterns, scene.name);
}

v1::SceneSpec ConfiguredScene(const SweepConfiguration& configuration, const BenchScene& scene) {
  v1::SceneSpec configured = scene.scene;
  v1::RenderSettings render = configuration.render;
  render.set_method(configuration.method);
  render.set_width(scene.scene.render().width());
  render.set_height(scene.scene.render().height());
  *configured.mutable_render() = render;
  if (configuration.plan_budget_db) {
    const v1::SceneSpec full = WithDefaults(configured);
    return ApplyPlan(configured, PlanScene(full, BuildSceneGeometry(full, FileMeshResolver({})),
                                           *configuration.plan_budget_db, StandardSweepVariations()));
  }
  for (v1::SceneObject& object : *configured.mutable_objects()) {
    if (object.has_fabric()) *object.mutable_fabric()->mutable_precompute() = configuration.precompute;
  }
  return configured;
}

SweepGrid LoadSweepGrid(const std::filesystem::path& grid_file) {
  const std::string where = grid_file.string() + ": ";
  json file;
  try {
    file = json::parse(ReadFile(grid_file));
  } catch (const json::parse_error& e) {
    throw Error(ErrorCode::kInvalidArgument, where + "not JSON: " + e.what());
  }
  try {
    static const std::set<std::string> kFields = {"comment",          "scene_set",      "scenes",
                                                  "ground_truth_samples", "flicker_frames", "flicker_shift_pixels",
                                                  "precompute",       "render",         "configurations"};
    for (const auto& [key, value] : file.items()) {
      if (!kFields.contains(key)) throw Error(ErrorCode::kInvalidArgument, key + ": unknown field");
    }
    SweepGrid grid;
    grid.name = grid_file.stem().string();
    if (!file.contains("scene_set")) throw Error(ErrorCode::kInvalidArgument, "scene_set: missing");
    const auto patterns = Patterns(file, "scenes");
    for (BenchScene& scene : LoadBenchScenes(grid_file.parent_path() / file.at("scene_set").get<std::string>())) {
      if (patterns.empty() || Matches(patterns, scene.name)) grid.scenes.push_back(std::move(scene));
    }
    if (grid.scenes.empty()) throw Error(ErrorCode::kInvalidArgument, "scenes: no bench scene matches");
    grid.ground_truth_samples = file.value("ground_truth_samples", grid.ground_truth_samples);
    grid.flicker_frames = file.value("flicker_frames", grid.flicker_frames);
    grid.flicker_shift_pixels = file.value("flicker_shift_pixels", grid.flicker_shift_pixels);
    if (grid.flicker_frames < 1 || grid.flicker_frames > 16) {
      throw Error(ErrorCode::kInvalidArgument, "flicker_frames: " + std::to_string(grid.flicker_frames) +
                                                   " outside [1, 16] (1 = no flicker measurement)");
    }
    if (!(grid.flicker_shift_pixels > 0.0 && grid.flicker_shift_pixels <= 8.0)) {
      throw Error(ErrorCode::kInvalidArgument, "flicker_shift_pixels: must lie in (0, 8]");
    }

    const auto base_precompute = Merged(v1::PrecomputeSettings(), file, "precompute", "precompute");
    const auto base_render = Merged(v1::RenderSettings(), file, "render", "render");
    if (!file.contains("configurations") || !file.at("configurations").is_array() ||
        file.at("configurations").empty()) {
      throw Error(ErrorCode::kInvalidArgument, "configurations: a non-empty list");
    }
    std::set<std::string> names;
    for (const json& entry : file.at("configurations")) {
      SweepConfiguration configuration;
      configuration.name = entry.value("name", "");
      const std::string field = "configurations[" + configuration.name + "]";
      if (configuration.name.empty()) throw Error(ErrorCode::kInvalidArgument, "configurations[]: a name is required");
      if (!names.insert(configuration.name).second) {
        throw Error(ErrorCode::kInvalidArgument, field + ": the name is used twice");
      }
      for (const auto& [key, value] : entry.items()) {
        if (key != "name" && key != "method" && key != "precompute" && key != "render" && key != "scenes" &&
            key != "plan_budget_db") {
          throw Error(ErrorCode::kInvalidArgument, field + "." + key + ": unknown field");
        }
      }
      const std::string method = entry.value("method", "svbrdf");
      const FabricMethod* fabric_method = MethodNamed(method);
      if (method != "reference" && method != "lumislice" && fabric_method == nullptr) {
        throw Error(ErrorCode::kInvalidArgument,
                    field + ".method: '" + method + "' is not reference, lumislice, " + MethodNames());
      }
      configuration.method = method == "reference"   ? v1::RENDER_METHOD_REFERENCE
                             : method == "lumislice" ? v1::RENDER_METHOD_LUMISLICE
                                                     : v1::RENDER_METHOD_SVBRDF;
      configuration.precompute = Merged(base_precompute, entry, "precompute", field + ".precompute");
      // A fabric method: the GPU renders with it (precompute.method).
      if (fabric_method != nullptr) configuration.precompute.set_method(fabric_method->id());
      configuration.render = Merged(base_render, entry, "render", field + ".render");
      configuration.scene_patterns = Patterns(entry, field + ".scenes");
      if (entry.contains("plan_budget_db")) {
        if (entry.contains("precompute") || configuration.method != v1::RENDER_METHOD_SVBRDF) {
          throw Error(ErrorCode::kInvalidArgument,
                      field + ".plan_budget_db: the planner chooses svbrdf's precompute; give no precompute");
        }
        configuration.plan_budget_db = entry.at("plan_budget_db").get<double>();
      }
      bool any = false;
      for (const BenchScene& scene : grid.scenes) {
        if (!grid.Applies(configuration, scene)) continue;
        any = true;
        ThrowIfAny(Validate(WithDefaults(ConfiguredScene(configuration, scene)), field + "@" + scene.name));
      }
      if (!any) throw Error(ErrorCode::kInvalidArgument, field + ".scenes: no scene of the grid matches");
      grid.configurations.push_back(std::move(configuration));
    }
    return grid;
  } catch (const Error& e) {
    if (e.code() != ErrorCode::kInvalidArgument) throw;
    throw Error(e.code(), where + e.what());
  } catch (const json::exception& e) {
    throw Error(ErrorCode::kInvalidArgument, where + e.what());
  }
}

}  // namespace loom::lab
