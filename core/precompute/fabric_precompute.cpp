#include "core/precompute/fabric_precompute.h"

#include <optional>
#include <string>
#include <vector>

#include "core/fabric/fabric_tile.h"
#include "core/methods/colour_sheets.h"
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

  // Each sheet (one, or with colour components one per three components) and each
  // side of it (with a back sheet, two) takes an equal part of the bar: its
  // acquisition, then its build.
  const v1::PrecomputeSettings full = WithDefaults(settings);
  const bool back = AcquiresTransmission(fabric, settings);
  const std::vector<std::optional<SheetChannels>> sheets = [&] {
    std::vector<std::optional<SheetChannels>> channels;
    if (!full.colour_components()) return decltype(channels){std::nullopt};
    for (const SheetChannels& sheet : ColourSheetChannels(tile.materials.size())) channels.emplace_back(sheet);
    return channels;
  }();
  const double parts = static_cast<double>(sheets.size()) * (back ? 2.0 : 1.0);
  const FabricMethod& method = MethodOf(full.method());
  double part = 0.0;
  const auto side = [&](const FabricTile& sheet_tile, LightSide light_side, const std::string& name) {
    const double start = part++;
    const auto span = [&](double from, double to, std::string prefix) {
      return [&report, start, from, to, parts, prefix = std::move(prefix)](double f, std::string_view stage) {
        report((start + from + (to - from) * f) / parts, prefix + std::string(stage));
      };
    };
    AcquireStats acquire_stats;
    const RadianceSamples samples = Acquire(sheet_tile, settings, span(0.0, kAcquireShare, name + "acquisition: "),
                                            &acquire_stats, {}, light_side);
    if (start == 0.0) {
      figures.acquisition = acquire_stats;
      figures.mean_alpha = samples.MeanAlpha();
    } else {
      figures.acquisition.seconds += acquire_stats.seconds;
      figures.acquisition.rays += acquire_stats.rays;
    }
    return method.Build(light_side == LightSide::kBack ? MirroredLights(samples) : samples, full,
                        span(kAcquireShare, 1.0, name + std::string(method.name()) + ": "));
  };
  std::unique_ptr<FabricAsset> asset;
  for (size_t s = 0; s < sheets.size(); ++s) {
    const FabricTile sheet_tile = sheets[s] ? ComponentTile(tile, *sheets[s]) : tile;
    const std::string sheet_name = sheets.size() > 1 ? "colour sheet " + std::to_string(s + 1) + ": " : "";
    std::unique_ptr<FabricAsset> sheet = side(sheet_tile, LightSide::kFront, sheet_name + (back ? "front: " : ""));
    if (back) sheet->set_back(side(sheet_tile, LightSide::kBack, sheet_name + "back: "));
    if (sheets[s]) sheet->set_colour_channels(*sheets[s]);
    if (s == 0) {
      asset = std::move(sheet);
    } else {
      asset->add_colour_sheet(std::move(sheet));
    }
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
