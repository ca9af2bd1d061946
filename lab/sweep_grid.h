#pragma once
// A sweep grid file (bench/sweep.json, bench/sweep_quick.json): which bench scenes,
// which configurations, and how errors are measured. Configurations are listed, not
// a factorial: each names what it changes from the grid's base settings, so a grid
// can vary one setting at a time around the default and add a few combinations.
//
//   {
//     "scene_set": "scenes/bench_set.json",       // relative to the grid file
//     "scenes": ["stockinette.flat0.*", ...],      // name globs; absent = every scene
//     "ground_truth_samples": 256,                 // reference spp of the ground truth
//     "flicker_frames": 3,                         // frames of the flicker camera move
//     "flicker_shift_pixels": 0.55,                // camera pan between them (pixels)
//     "precompute": {PrecomputeSettings},          // base of every svbrdf configuration
//     "render": {RenderSettings},                  // base of every configuration
//     "configurations": [
//       {"name": "default"},
//       {"name": "res8", "precompute": {"spatial_resolution": 8}},
//       {"name": "reference-16", "method": "reference", "render": {"reference_samples": 16}},
//       {"name": "volumetric", "method": "lumislice"},   // knit scenes: lumislice renderer
//       {"name": "lobes3-far", "precompute": {"lobes": 3}, "scenes": ["*.far"]},
//       {"name": "plan", "plan_budget_db": 0.5}
//     ]
//   }
//
// A configuration with "plan_budget_db" lets the planner (core/plan/precompute_plan.h)
// choose each scene's precompute settings within that budget, instead of "precompute".
// Settings are protobuf JSON merged field by field onto the base (a zero keeps the
// base's value, as everywhere in Loom's specs). Every scene × configuration is
// validated on load, so a bad grid fails before any work, naming the field.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "lab/bench_scenes.h"
#include "loom/v1/precompute.pb.h"
#include "loom/v1/scene.pb.h"

namespace loom::lab {

struct SweepConfiguration {
  std::string name;
  v1::RenderMethod method = v1::RENDER_METHOD_SVBRDF;
  v1::PrecomputeSettings precompute;  // base merged with the configuration's
  v1::RenderSettings render;          // base merged with the configuration's
  std::vector<std::string> scene_patterns;  // empty: every scene of the grid
  std::optional<double> plan_budget_db;     // set: the planner chooses the precompute
};

struct SweepGrid {
  std::string name;  // the file's stem: results go to <out>/<name>.csv
  std::vector<BenchScene> scenes;
  std::vector<SweepConfiguration> configurations;
  uint32_t ground_truth_samples = 256;
  int flicker_frames = 3;
  double flicker_shift_pixels = 0.55;

  bool Applies(const SweepConfiguration& configuration, const BenchScene& scene) const;
};

// The scene as this configuration renders it: the configuration's render settings
// (frame size kept from the scene) and, on every fabric, its precompute settings
// (or the plan's). Defaults not applied.
v1::SceneSpec ConfiguredScene(const SweepConfiguration& configuration, const BenchScene& scene);

SweepGrid LoadSweepGrid(const std::filesystem::path& grid_file);

}  // namespace loom::lab
