// loom-lab geometry | acquire: a fabric's micro-geometry and its radiance samples.

#include <chrono>
#include <cstdio>

#include "core/acquire/acquisition.h"
#include "core/fabric/fabric_tile.h"
#include "core/scene/obj_writer.h"
#include "core/spec/spec_json.h"
#include "lab/lab_command.h"
#include "lab/progress_bar.h"

namespace loom::lab {
namespace {

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

nlohmann::json TileJson(const FabricTile& tile) {
  return {{"yarn_curves", tile.curves.size()},
          {"triangles", tile.mesh.triangle_count()},
          {"vertices", tile.mesh.positions.size()},
          {"materials", tile.materials.size()},
          {"z_min", tile.z_min},
          {"z_max", tile.z_max}};
}

}  // namespace

LabCommand AddGeometryCommand(CLI::App& app, const LabFlags& flags) {
  struct Options {
    std::string fabric, obj;
    std::vector<int> tiles = {1, 1};
  };
  auto options = std::make_shared<Options>();
  auto* command = app.add_subcommand("geometry", "Build a fabric's periodic tile and export it as OBJ with normals");
  command->add_option("fabric", options->fabric, "Fabric spec file (JSON)")->required();
  command->add_option("--obj", options->obj, "Output OBJ file")->required();
  command->add_option("--tiles", options->tiles, "Repeat the tile NX NY times")->expected(2)->check(CLI::Range(1, 64));
  return {command, [&flags, options] {
            const auto start = std::chrono::steady_clock::now();
            const FabricTile tile = BuildFabricTile(LoadSpecFile<v1::FabricSpec>(options->fabric, "fabric"));
            const double build_seconds = SecondsSince(start);
            WriteObj(tile.mesh, options->obj, options->tiles[0], options->tiles[1]);
            if (flags.json) {
              nlohmann::json figures = TileJson(tile);
              figures["obj"] = options->obj;
              figures["tiles"] = options->tiles;
              figures["build_seconds"] = build_seconds;
              PrintJson(figures);
            } else {
              std::printf("wrote %s: %zu triangles a tile × %d×%d tiles, %zu yarn curves (built in %.3f s)\n",
                          options->obj.c_str(), tile.mesh.triangle_count(), options->tiles[0], options->tiles[1],
                          tile.curves.size(), build_seconds);
            }
            return 0;
          }};
}

LabCommand AddAcquireCommand(CLI::App& app, const LabFlags& flags) {
  struct Options {
    std::string fabric, settings, out;
    unsigned threads = 0;
  };
  auto options = std::make_shared<Options>();
  auto* command = app.add_subcommand(
      "acquire", "Render a fabric's radiance samples (views × lights per texel) into a samples file");
  command->add_option("fabric", options->fabric, "Fabric spec file (JSON)")->required();
  command->add_option("--settings", options->settings, "Precompute settings file (JSON); defaults if absent");
  command->add_option("--out,-o", options->out, "Output samples file (format: core/acquire/radiance_samples.h)")
      ->required();
  command->add_option("--threads", options->threads, "Worker threads (0 = every core)");
  return {command, [&flags, options] {
            const auto fabric = LoadSpecFile<v1::FabricSpec>(options->fabric, "fabric");
            const auto settings = options->settings.empty()
                                      ? v1::PrecomputeSettings()
                                      : LoadSpecFile<v1::PrecomputeSettings>(options->settings, "precompute");
            const auto start = std::chrono::steady_clock::now();
            const FabricTile tile = BuildFabricTile(fabric);
            const double geometry_seconds = SecondsSince(start);
            AcquireStats stats;
            AcquireOptions acquire_options;
            acquire_options.threads = options->threads;
            RadianceSamples samples;
            {
              ProgressBar bar("acquire");
              samples = Acquire(
                  tile, settings, [&bar](double fraction, std::string_view stage) { bar.Update(fraction, stage); },
                  &stats, acquire_options);
            }
            WriteRadianceSamples(samples, options->out);
            if (flags.json) {
              PrintJson({{"out", options->out},
                         {"tile", TileJson(tile)},
                         {"geometry_seconds", geometry_seconds},
                         {"seconds", stats.seconds},
                         {"rays", stats.rays},
                         {"rays_per_second", stats.rays_per_second()},
                         {"threads", stats.threads},
                         {"resolution", samples.resolution},
                         {"views", samples.view_count()},
                         {"lights", samples.light_count()},
                         {"mean_alpha", samples.MeanAlpha()},
                         {"non_finite_values", stats.non_finite_values}});
            } else {
              std::printf("wrote %s: %u² texels × %zu views × %zu lights in %.2f s (%.2f M rays/s on %u threads), "
                          "mean alpha %.3f\n",
                          options->out.c_str(), samples.resolution, samples.view_count(), samples.light_count(),
                          stats.seconds, stats.rays_per_second() * 1e-6, stats.threads, samples.MeanAlpha());
            }
            return 0;
          }};
}

}  // namespace loom::lab
