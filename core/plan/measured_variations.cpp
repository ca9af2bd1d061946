#include "core/plan/measured_variations.h"

namespace loom {

FootprintClass ClassifyFootprint(double tile_pixels) {
  if (tile_pixels >= kNearFromTilePixels) return FootprintClass::kNear;
  if (tile_pixels >= kMidFromTilePixels) return FootprintClass::kMid;
  return FootprintClass::kFar;
}

const char* FootprintClassName(FootprintClass footprint) {
  switch (footprint) {
    case FootprintClass::kNear: return "near";
    case FootprintClass::kMid: return "mid";
    case FootprintClass::kFar: return "far";
  }
  return "?";
}

const std::vector<MeasuredVariation>& StandardSweepVariations() {
  // Generated: loom-lab plan --distill docs/results/sweep.csv > core/plan/standard_sweep_table.inc
  static const std::vector<MeasuredVariation> kVariations = {
#include "core/plan/standard_sweep_table.inc"
  };
  return kVariations;
}

}  // namespace loom
