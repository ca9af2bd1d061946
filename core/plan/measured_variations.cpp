#include "core/plan/measured_variations.h"

namespace loom {

const std::vector<MeasuredVariation>& StandardSweepVariations() {
  // Generated: loom-lab plan --distill docs/results/sweep.csv > core/plan/standard_sweep_table.inc
  static const std::vector<MeasuredVariation> kVariations = {
#include "core/plan/standard_sweep_table.inc"
  };
  return kVariations;
}

}  // namespace loom
