#include "lab/fabric_cache.h"

#include <nlohmann/json.hpp>

#include <cmath>

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
    result.asset = ReadAnyFabricAsset(directory);
    result.loaded = true;
    result.asset_bytes = DirectoryBytes(directory);
    // An asset stored by another tool has no timing file: its build time is the
    // best figure left.
    result.precompute_seconds = result.asset->build_seconds();
    result.precompute_cpu_seconds = NAN;
    if (std::filesystem::exists(directory / kTimingFile)) {
      const nlohmann::json timing = nlohmann::json::parse(ReadFile(directory / kTimingFile));
      result.precompute_seconds = timing.at("seconds").get<double>();
      result.precompute_cpu_seconds = timing.value("cpu_seconds", NAN);
    }
    return result;
  }
  ProgressBar bar("precompute " + fabric.key.substr(0, 8));
  const Stopwatch stopwatch;
  const ProcessCpuStopwatch cpu;
  result.asset = PrecomputeAsset(fabric.fabric, fabric.settings,
                                 [&bar](double f, std::string_view stage) { bar.Update(f, stage); });
  result.precompute_seconds = stopwatch.Seconds();
  result.precompute_cpu_seconds = cpu.Seconds();
  if (!directory.empty()) {
    result.asset->Write(fabric.settings, fabric.key, directory);
    // Render what was stored (half floats where the asset allows them), as every
    // later run and every user does, not the full-precision build in memory.
    result.asset = ReadAnyFabricAsset(directory);
    result.asset_bytes = DirectoryBytes(directory);
    WriteFileAtomic(directory / kTimingFile,
                    nlohmann::json({{"seconds", result.precompute_seconds}, {"cpu_seconds", result.precompute_cpu_seconds}})
                        .dump());
  }
  return result;
}

}  // namespace loom::lab
