#pragma once
// "Model no more than a scene needs" (issue 7, DESIGN.md "Measurement protocol"):
// from a scene, the least precompute that serves each of its fabrics, and why.
//
// For each distinct fabric without explicit settings:
// 1. Footprint. The largest on-screen tile over its objects
//    (core/plan/screen_footprint.h) bounds the texels that can ever show: the
//    finest useful resolution is the smallest power of two ≥ that many pixels
//    (at least 4, at most the default). It also picks the footprint class.
// 2. Kind. The fabric's kind (core/plan/fabric_kind.h: knit or woven, glossy or
//    matte) and the footprint class make the class of scene whose measurements
//    apply. A kind the sweep did not measure is planned from every kind's
//    measurements of its footprint class, taking for each variation the worst
//    loss and the highest cost any kind showed; so is a variation measured on
//    fewer than kMinClassScenes scenes of the class (a worst case over two scenes
//    is none: docs/results/plan.md, "Plan against defaults on the bench scenes").
// 3. Measurements. Each measured variation of the class (resolution — never below
//    the footprint's bound —, directions, lobes, LUT, or another fabric method at
//    its defaults, whose asset is at most kMaxPlannedBytesRatio times the
//    defaults') is a candidate if its WORST
//    measured PSNR loss, over every scene of its class the sweep measured, is within
//    the error budget — not merely its mean (a class's mean can hide one fabric
//    losing much among others losing nothing). The plan takes the candidate that
//    saves the most precompute time, and only one: the sweep measures variations one
//    at a time, and their combination is not the sum of their losses (measured in
//    docs/accuracy.md and docs/results/plan.md). So a
//    plan is a configuration the sweep measured on every scene of its class, and
//    met the budget on each of them by construction. No candidate: the defaults.
// The error budget is the PSNR, in dB against the ground truth, the plan may lose
// against the default settings: svbrdf's absolute accuracy is the fitted model's
// (docs/accuracy.md), so the budget says how much of it one trades for speed.

#include <string>
#include <vector>

#include "core/plan/fabric_kind.h"
#include "core/plan/measured_variations.h"
#include "core/plan/screen_footprint.h"
#include "core/scene/scene_geometry.h"
#include "loom/v1/precompute.pb.h"
#include "loom/v1/scene.pb.h"

namespace loom {

inline constexpr double kDefaultErrorBudgetDb = 0.5;
inline constexpr uint32_t kMinPlannedResolution = 4;
inline constexpr int kMinClassScenes = 3;
// A plan saves precompute; it may not buy it with an asset this many times the
// defaults' (the tabulated ceiling's is ~60 times: a measurement, not a plan).
inline constexpr double kMaxPlannedBytesRatio = 10.0;

struct FabricPlan {
  std::string key;                   // FabricKey of the planned settings
  std::vector<std::string> objects;  // names (or "#index") of the objects using it
  v1::FabricSpec fabric;
  v1::PrecomputeSettings settings;   // defaults applied
  bool explicit_settings = false;    // the scene gave settings: kept as they are
  TileFootprint footprint;
  FootprintClass footprint_class = FootprintClass::kMid;
  FabricKind fabric_kind = FabricKind::kKnitMatte;
  bool kind_measured = true;              // false: planned from every kind's worst (step 2)
  uint32_t footprint_resolution = 0;      // the finest resolution the footprint can show
  std::vector<std::string> chosen;        // the measured variation taken (none: the defaults)
  double predicted_psnr_loss_db = 0.0;    // worst measured loss of `chosen`
  double predicted_precompute_ratio = 1.0;  // its measured ratios
  double predicted_bytes_ratio = 1.0;
  std::vector<std::string> reasons;       // one line per decision, for people
};

struct ScenePlan {
  double error_budget_db = kDefaultErrorBudgetDb;
  std::vector<FabricPlan> fabrics;
};

// `scene` with defaults applied and validated, `meshes` = BuildSceneGeometry(scene),
// `variations` usually StandardSweepVariations(). Error(kInvalidArgument) if the
// budget is negative or not finite.
ScenePlan PlanScene(const v1::SceneSpec& scene, const std::vector<SceneMesh>& meshes, double error_budget_db,
                    const std::vector<MeasuredVariation>& variations);

// `scene` with each planned fabric's settings set on its objects.
v1::SceneSpec ApplyPlan(v1::SceneSpec scene, const ScenePlan& plan);

}  // namespace loom
