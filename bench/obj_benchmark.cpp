// What a scene's meshes cost to parse and prepare at the caps of
// core/spec/limits.h (issue 22; figures for docs/operations.md "Limits", not a
// test): the time and the peak resident memory of BuildSceneGeometry, which is
// what loom-server's SubmitJob does for a render (in one parse slot) and a worker
// before it renders.
//   grid:  a 1414×1414-quad grid with v/vt/vn, ~4M triangles on 2M vertices (a
//          large real mesh)
//   worst: 4M triangles on 4M distinct vertices, 4M of each attribute (every cap
//          reached at once: the bound)
//   loom_obj_benchmark [--benchmark_filter=...]
// The OBJ is written to a temporary file first and streamed from it, as the server
// streams an uploaded artifact. peak_rss_mib is the process's peak while parsing
// (VmHWM, reset before; Linux).

#include <benchmark/benchmark.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/scene/scene_geometry.h"
#include "core/spec/limits.h"
#include "core/spec/spec_json.h"

namespace loom {
namespace {

int64_t StatusKib(const char* field) {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind(field, 0) == 0) return std::stoll(line.substr(std::string(field).size()));
  }
  return 0;
}

void ResetPeakRss() { std::ofstream("/proc/self/clear_refs") << "5"; }

std::filesystem::path GridObj() {
  const std::filesystem::path path = std::filesystem::temp_directory_path() / "loom_obj_benchmark_grid.obj";
  std::ofstream out(path);
  const int quads = 1414, side = quads + 1;
  for (int y = 0; y < side; ++y) {
    for (int x = 0; x < side; ++x) out << "v " << x << ' ' << y << " 0\n";
  }
  for (int y = 0; y < side; ++y) {
    for (int x = 0; x < side; ++x) out << "vt " << x / double(quads) << ' ' << y / double(quads) << '\n';
  }
  out << "vn 0 0 1\n";
  for (int y = 0; y < quads; ++y) {
    for (int x = 0; x < quads; ++x) {
      const int a = y * side + x + 1, b = a + 1, c = a + side + 1, d = a + side;
      out << "f " << a << '/' << a << "/1 " << b << '/' << b << "/1 " << c << '/' << c << "/1 " << d << '/' << d
          << "/1\n";
    }
  }
  return path;
}

std::filesystem::path WorstObj() {
  const std::filesystem::path path = std::filesystem::temp_directory_path() / "loom_obj_benchmark_worst.obj";
  std::ofstream out(path);
  const int64_t n = kMaxMeshVertices, side = 2000;
  // Vertex i on a 2000-wide grid at (i % 2000, i / 2000); triangle t on vertices
  // t, t + 1 and t + 2000 (modulo n), so that every cap is met at once.
  for (int64_t i = 0; i < n; ++i) out << "v " << i % side << ' ' << i / side << " 0\n";
  for (int64_t i = 0; i < n; ++i) out << "vt " << (i % side) * 1e-3 << ' ' << (i / side) * 1e-3 << '\n';
  for (int64_t i = 0; i < n; ++i) out << "vn 0 " << (i % 7) * 1e-3 << " 1\n";
  for (int64_t t = 0; t < kMaxMeshTriangles; ++t) {
    out << 'f';
    for (const int64_t v : {t, t + 1, t + side}) out << ' ' << v % n + 1 << '/' << v % n + 1 << '/' << v % n + 1;
    out << '\n';
  }
  return path;
}

void Parse(benchmark::State& state, const std::filesystem::path& obj) {
  const v1::SceneSpec scene = ParseSpecJson<v1::SceneSpec>(
      R"({"objects": [{"name": "cloth", "mesh": {"obj_path": ")" + obj.filename().string() +
          R"("}, "fabric": {"fabric": {"knit": {}}}}], "camera": {"position": {"x": 0, "y": -3, "z": 1}}})",
      "scene");
  const int64_t before_kib = StatusKib("VmRSS:");
  size_t triangles = 0, vertices = 0;
  for (auto _ : state) {
    ResetPeakRss();
    const std::vector<SceneMesh> meshes = BuildSceneGeometry(scene, FileMeshResolver(obj.parent_path()));
    triangles = meshes[0].mesh.triangle_count();
    vertices = meshes[0].mesh.positions.size();
    state.counters["peak_rss_mib"] = static_cast<double>(StatusKib("VmHWM:") - before_kib) / 1024.0;
  }
  state.counters["file_mib"] = static_cast<double>(std::filesystem::file_size(obj)) / (1 << 20);
  state.counters["triangles"] = static_cast<double>(triangles);
  state.counters["vertices"] = static_cast<double>(vertices);
  std::filesystem::remove(obj);
}

void Grid(benchmark::State& state) { Parse(state, GridObj()); }
void Worst(benchmark::State& state) { Parse(state, WorstObj()); }

BENCHMARK(Grid)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();
BENCHMARK(Worst)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

}  // namespace
}  // namespace loom

BENCHMARK_MAIN();
