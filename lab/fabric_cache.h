#pragma once
// A directory of fabric assets (any method) by cache key, shared by `loom-lab render
// --fabric-cache` and `loom-lab sweep`: a fabric found there is read, one that is
// not is precomputed and stored, so each distinct (fabric, settings) is fitted once
// across runs. Next to each asset the cache keeps what the precompute cost, wall and
// CPU seconds (`precompute.json`), so a later run still reports it.

#include <cstdint>
#include <filesystem>

#include <memory>

#include "core/methods/fabric_method.h"
#include "core/render/scene_render.h"

namespace loom::lab {

struct CachedFabric {
  std::unique_ptr<FabricAsset> asset;
  double precompute_seconds = 0.0;  // geometry + acquisition + build, when it was computed
  // Its CPU time (every thread), which the machine's load does not inflate; NaN
  // for an asset cached without it.
  double precompute_cpu_seconds = 0.0;
  uint64_t asset_bytes = 0;         // the asset's files on disk; 0 when not stored
  bool loaded = false;              // read from the cache rather than computed now
};

// `cache` empty: always precompute, store nothing. Shows a progress bar while it
// precomputes.
CachedFabric LoadOrPrecompute(const SceneFabric& fabric, const std::filesystem::path& cache);

}  // namespace loom::lab
