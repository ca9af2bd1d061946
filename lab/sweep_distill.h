#pragma once
// Distils a sweep CSV into what the planner reads (core/plan/measured_variations.h):
// for each configuration that changes one precompute setting of the baseline
// configuration (resolution, possibly with its supersampling; directions; lobes; LUT;
// or the fabric method, another method at its own defaults) and renders like it, per
// class of scene — footprint class (of the row's measured footprint, as the planner
// classifies a scene) and fabric kind (the row's fabric_kind) — the mean and the worst
// PSNR change and the precompute CPU-time (precompute_cpu_seconds: wall time grows with
// the machine's load, which changed while the sweep ran) and asset-byte ratios over the
// scenes both measured. A class is given only where the variation ran on every scene of
// the class the baseline ran on (the worst case of part of a class says nothing of the
// rest). Rows whose image held NaN (PSNR not finite) count as run but leave no figure,
// as the chart leaves them out.
//
// Repeats. Rows of one scene whose settings columns all agree but for the seed (which
// picks acquisition's ray jitter) measure the same figure: each stands for the mean
// PSNR, precompute time and bytes over the seeds measured (a seed found twice counts
// once), the baseline and the variations alike. Far away one fit's PSNR moves with
// the seed by about the planner's budget (docs/results/plan.md), so a single fit
// there says more about its draw than about its settings.

#include <string>
#include <vector>

#include "core/plan/measured_variations.h"
#include "lab/csv_table.h"

namespace loom::lab {

// Error(kInvalidArgument) if the CSV has no GPU rows of `baseline`, or if they
// were rendered otherwise than the default render settings or acquired on another
// sampling plane than the default (core/spec/defaults.h), which the planner's figures
// describe.
std::vector<MeasuredVariation> DistillSweep(const CsvTable& table, const std::string& baseline = "default");

// The variations as C++ initialisers for core/plan/standard_sweep_table.inc, after a
// comment naming the fields.
std::string VariationsAsCpp(const std::vector<MeasuredVariation>& variations);

}  // namespace loom::lab
