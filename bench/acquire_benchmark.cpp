// Acquisition speed (issue 3; a figure, not a test): the standard knit tile
// (stockinette, default yarn) and a 3/1 twill, 32×32 texels, 64 views × 64 lights,
// 1 bounce, 2×2 sub-samples per texel (the default, "4×") and 4×4.
//   loom_acquire_benchmark [--benchmark_filter=...]
//   arguments: threads (0 = all cores), supersampling

#include <benchmark/benchmark.h>

#include "core/acquire/acquisition.h"
#include "core/fabric/fabric_tile.h"
#include "core/spec/spec_json.h"

namespace loom {
namespace {

void Acquisition(benchmark::State& state, const char* fabric_json) {
  const FabricTile tile = BuildFabricTile(ParseSpecJson<v1::FabricSpec>(fabric_json, "fabric"));
  v1::PrecomputeSettings settings;
  settings.set_spatial_resolution(32);
  settings.set_view_directions(64);
  settings.set_light_directions(64);
  settings.set_supersampling(static_cast<uint32_t>(state.range(1)));
  settings.set_indirect_bounces(1);
  AcquireStats stats;
  double rays = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(Acquire(tile, settings, {}, &stats, {.threads = static_cast<unsigned>(state.range(0))}));
    rays += static_cast<double>(stats.rays);
  }
  state.counters["triangles"] = static_cast<double>(tile.mesh.triangle_count());
  state.counters["threads"] = stats.threads;
  state.counters["rays"] = static_cast<double>(stats.rays);
  state.counters["rays_per_second"] = benchmark::Counter(rays, benchmark::Counter::kIsRate);
  state.counters["tiles_in_scene"] = stats.tiles_x * stats.tiles_y;
}

void StandardKnit(benchmark::State& state) { Acquisition(state, R"({"knit": {}})"); }
void Twill31(benchmark::State& state) {
  Acquisition(state, R"({"woven": {"pattern": "WEAVE_PATTERN_TWILL", "n": 3, "m": 1, "gap_ratio": 0.1}})");
}

BENCHMARK(StandardKnit)
    ->ArgNames({"threads", "supersampling"})
    ->Args({1, 2})
    ->Args({0, 2})
    ->Args({0, 4})
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->UseRealTime();
BENCHMARK(Twill31)->ArgNames({"threads", "supersampling"})->Args({0, 2})->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

}  // namespace
}  // namespace loom

BENCHMARK_MAIN();
