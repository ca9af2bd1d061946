#pragma once
// The fabric precompute: spec → periodic tile geometry → radiance samples → the
// asset of the settings' method (DESIGN.md "Core engine" 1-3). One entry point for
// loom-lab and the render workers.

#include <functional>
#include <string_view>

#include "core/acquire/acquisition.h"
#include "core/fit/fabric_fit.h"
#include "core/methods/fabric_method.h"
#include "loom/v1/fabric.pb.h"
#include "loom/v1/precompute.pb.h"

namespace loom {

struct PrecomputeStats {
  double geometry_seconds = 0.0;
  size_t tile_triangles = 0;
  AcquireStats acquisition;  // seconds and rays: the sum over every sheet and side
  double mean_alpha = 0.0;  // the build's time is FabricAsset::build_seconds
};

// fraction in [0, 1] over the whole precompute; stage names the step. Called on
// the calling thread; throwing from it cancels.
using PrecomputeProgress = std::function<void(double fraction, std::string_view stage)>;

// Validates both specs first (Error(kInvalidArgument) naming the field).
std::unique_ptr<FabricAsset> PrecomputeAsset(const v1::FabricSpec& fabric, const v1::PrecomputeSettings& settings,
                                             const PrecomputeProgress& progress = {},
                                             PrecomputeStats* stats = nullptr);

// PrecomputeAsset with the svbrdf method whatever settings.method says: the fitted
// BRDF array itself.
FittedFabric PrecomputeFabric(const v1::FabricSpec& fabric, const v1::PrecomputeSettings& settings,
                              const PrecomputeProgress& progress = {}, PrecomputeStats* stats = nullptr);

}  // namespace loom
