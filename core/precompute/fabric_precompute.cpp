#include "core/precompute/fabric_precompute.h"

#include <string>

#include "core/fabric/fabric_tile.h"
#include "core/spec/validate.h"
#include "core/util/stopwatch.h"

namespace loom {
namespace {

// Shares of the progress bar: acquisition and fitting take comparable time on
// the standard knit; geometry is instant.
constexpr double kAcquireShare = 0.45;

}  // namespace

FittedFabric PrecomputeFabric(const v1::FabricSpec& fabric, const v1::PrecomputeSettings& settings,
                              const PrecomputeProgress& progress, PrecomputeStats* stats) {
  ThrowIfAny(Validate(fabric, settings));
  const auto report = [&progress](double fraction, std::string_view stage) {
    if (progress) progress(fraction, stage);
  };
  PrecomputeStats local;
  PrecomputeStats& figures = stats != nullptr ? *stats : local;

  report(0.0, "geometry");
  const Stopwatch geometry_time;
  const FabricTile tile = BuildFabricTile(fabric);
  figures.geometry_seconds = geometry_time.Seconds();
  figures.tile_triangles = tile.mesh.triangle_count();

  const RadianceSamples samples = Acquire(
      tile, settings,
      [&report](double f, std::string_view stage) { report(kAcquireShare * f, "acquisition: " + std::string(stage)); },
      &figures.acquisition);
  figures.mean_alpha = samples.MeanAlpha();

  FittedFabric fitted = FitFabric(samples, settings, [&report](double f, std::string_view stage) {
    report(kAcquireShare + (1.0 - kAcquireShare) * f, "fit: " + std::string(stage));
  });
  fitted.sampling_height = tile.z_max;
  report(1.0, "done");
  return fitted;
}

}  // namespace loom
