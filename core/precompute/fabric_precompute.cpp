#include "core/precompute/fabric_precompute.h"

#include <string>

#include "core/fabric/fabric_tile.h"
#include "core/methods/svbrdf/svbrdf_method.h"
#include "core/spec/defaults.h"
#include "core/spec/validate.h"
#include "core/util/stopwatch.h"

namespace loom {
namespace {

// Shares of the progress bar: acquisition and svbrdf's fit take comparable time
// on the standard knit; geometry is instant.
constexpr double kAcquireShare = 0.45;

}  // namespace

std::unique_ptr<FabricAsset> PrecomputeAsset(const v1::FabricSpec& fabric, const v1::PrecomputeSettings& settings,
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

  const v1::PrecomputeSettings full = WithDefaults(settings);
  const FabricMethod& method = MethodOf(full.method());
  const std::string stage = std::string(method.name()) + ": ";
  std::unique_ptr<FabricAsset> asset =
      method.Build(samples, full, [&report, &stage](double f, std::string_view step) {
        report(kAcquireShare + (1.0 - kAcquireShare) * f, stage + std::string(step));
      });
  report(1.0, "done");
  return asset;
}

FittedFabric PrecomputeFabric(const v1::FabricSpec& fabric, const v1::PrecomputeSettings& settings,
                              const PrecomputeProgress& progress, PrecomputeStats* stats) {
  v1::PrecomputeSettings svbrdf = settings;
  svbrdf.set_method(v1::FABRIC_METHOD_SVBRDF);
  return static_cast<const SvbrdfAsset&>(*PrecomputeAsset(fabric, svbrdf, progress, stats)).fit();
}

}  // namespace loom
