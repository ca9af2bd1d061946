#pragma once
// What the standard sweep measured about cheaper precompute settings: for each
// class of scene — footprint class (near / mid / far) and fabric kind (knit or
// woven, glossy or matte: core/plan/fabric_kind.h) — and each variation of the
// default settings, how much PSNR against the ground truth it lost or gained (on
// average and on the class's worst scene) and what it cost in precompute time and
// asset bytes, relative to the defaults on the same scenes. The planner
// (core/plan/precompute_plan.h) chooses from these.
//
// StandardSweepVariations() is compiled in, distilled from the committed
// docs/results/sweep.csv and its repeats under other seeds (seeds.csv,
// far_seeds.csv; a figure is the mean over its seeds), and the other fabric methods
// of the methods sweep (methods.csv), by `loom-lab plan --distill` (lab/sweep_distill.h),
// so the server plans without reading files.

#include <cstdint>
#include <string>
#include <vector>

#include "core/plan/fabric_kind.h"
#include "loom/v1/precompute.pb.h"

namespace loom {

// Footprint classes by the largest on-screen tile (core/plan/screen_footprint.h),
// for scenes and sweep rows alike; the boundaries lie at the geometric means of the
// bench distances (a tile spans 64, 16 and 2 pixels across).
enum class FootprintClass { kNear, kMid, kFar };
inline constexpr double kNearFromTilePixels = 32.0;
inline constexpr double kMidFromTilePixels = 5.66;
FootprintClass ClassifyFootprint(double tile_pixels);
const char* FootprintClassName(FootprintClass footprint);  // "near", "mid", "far"

struct MeasuredVariation {
  std::string configuration;  // the sweep's name for it, e.g. "lobes1"
  FootprintClass footprint = FootprintClass::kMid;
  FabricKind fabric_kind = FabricKind::kKnitMatte;
  // The settings it changes; 0 (or -1 for lookup_table) = as the default.
  uint32_t spatial_resolution = 0;
  uint32_t directions = 0;  // view and light alike
  uint32_t lobes = 0;
  int lookup_table = -1;
  uint32_t supersampling = 0;
  double psnr_change_db = 0.0;        // mean over the class's scenes, minus the default's
  double worst_psnr_change_db = 0.0;  // the lowest over the class's scenes: what the planner budgets
  double precompute_ratio = 1.0;  // mean precompute CPU seconds over the default's
  double bytes_ratio = 1.0;
  int scenes = 0;                 // how many scenes the figures are over
  // Another fabric method at its own defaults (and the settings above unchanged);
  // unspecified: the default method.
  v1::FabricMethod method = v1::FABRIC_METHOD_UNSPECIFIED;
};

const std::vector<MeasuredVariation>& StandardSweepVariations();

}  // namespace loom
