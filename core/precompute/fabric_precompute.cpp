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

  // With a back sheet, each side takes half of the bar: its acquisition, then its build.
  const bool back = AcquiresTransmission(fabric, settings);
  const double sides = back ? 2.0 : 1.0;
  const v1::PrecomputeSettings full = WithDefaults(settings);
  const FabricMethod& method = MethodOf(full.method());
  const auto side = [&](LightSide light_side, double start, std::string_view name, AcquireStats* acquire_stats) {
    const auto span = [&](double from, double to, std::string prefix) {
      return [&report, start, from, to, sides, prefix = std::move(prefix)](double f, std::string_view stage) {
        report(start + (from + (to - from) * f) / sides, prefix + std::string(stage));
      };
    };
    const RadianceSamples samples =
        Acquire(tile, settings, span(0.0, kAcquireShare, std::string(name) + "acquisition: "), acquire_stats, {},
                light_side);
    if (light_side == LightSide::kFront) figures.mean_alpha = samples.MeanAlpha();
    return method.Build(light_side == LightSide::kBack ? MirroredLights(samples) : samples, full,
                        span(kAcquireShare, 1.0, std::string(name) + std::string(method.name()) + ": "));
  };
  std::unique_ptr<FabricAsset> asset = side(LightSide::kFront, 0.0, back ? "front: " : "", &figures.acquisition);
  if (back) {
    AcquireStats back_stats;
    asset->set_back(side(LightSide::kBack, 0.5, "back: ", &back_stats));
    figures.acquisition.seconds += back_stats.seconds;
    figures.acquisition.rays += back_stats.rays;
  }
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
