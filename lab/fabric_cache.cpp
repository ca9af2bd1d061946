#include "lab/fabric_cache.h"

#include <nlohmann/json.hpp>

#include "core/fit/fabric_asset.h"
#include "core/precompute/fabric_precompute.h"
#include "core/util/file_io.h"
#include "core/util/progress_bar.h"
#include "core/util/stopwatch.h"

namespace loom::lab {
namespace {

constexpr const char* kTimingFile = "precompute.json";

uint64_t DirectoryBytes(const std::filesystem::path& directory) {
  uint64_t bytes = 0;
  for (const auto& entry : std::filesystem::directory_iterator(directory)) {
    if (entry.is_regular_file() && entry.path().filename() != kTimingFile) bytes += entry.file_size();
  }
  return bytes;
}

}  // namespace

CachedFabric LoadOrPrecompute(const SceneFabric& fabric, const std::filesystem::path& cache) {
  const std::filesystem::path directory = cache.empty() ? std::filesystem::path() : cache / fabric.key;
  CachedFabric result;
  if (!directory.empty() && std::filesystem::exists(directory / "manifest.json")) {
    result.fit = ReadFabricAsset(directory);
    result.loaded = true;
    result.asset_bytes = DirectoryBytes(directory);
    // An asset stored by another tool has no timing file: its fit time is the best
    // figure left.
    result.precompute_seconds = std::filesystem::exists(directory / kTimingFile)
                                    ? nlohmann::json::parse(ReadFile(directory / kTimingFile)).at("seconds").get<double>()
                                    : result.fit.seconds;
    return result;
  }
  ProgressBar bar("precompute " + fabric.key.substr(0, 8));
  const Stopwatch stopwatch;
  result.fit = PrecomputeFabric(fabric.fabric, fabric.settings,
                                [&bar](double f, std::string_view stage) { bar.Update(f, stage); });
  result.precompute_seconds = stopwatch.Seconds();
  if (!directory.empty()) {
    WriteFabricAsset(result.fit, fabric.settings, fabric.key, directory);
    result.asset_bytes = DirectoryBytes(directory);
    WriteFileAtomic(directory / kTimingFile, nlohmann::json({{"seconds", result.precompute_seconds}}).dump());
  }
  return result;
}

}  // namespace loom::lab
