// loom-lab geometry | yarn-section | lumislice | acquire | fit | precompute: a fabric's
// micro-geometry, a yarn's section and lumislice, its radiance samples, the svbrdf fit
// of saved samples, and its asset (the cached one, of the settings' method).

#include <cstdio>

#include "core/acquire/acquisition.h"
#include "core/fabric/fabric_tile.h"
#include "core/fabric/yarn_material.h"
#include "core/fabric/yarn_section.h"
#include "core/image/image.h"
#include "core/methods/fabric_method.h"
#include "core/methods/lumislice/lumislice_table.h"
#include "core/precompute/fabric_precompute.h"
#include "core/scene/obj_writer.h"
#include "core/spec/defaults.h"
#include "core/spec/fabric_key.h"
#include "core/spec/limits.h"
#include "core/spec/spec_json.h"
#include "core/spec/validate.h"
#include "core/util/progress_bar.h"
#include "core/util/stopwatch.h"
#include "lab/lab_command.h"

namespace loom::lab {
namespace {

nlohmann::json TileJson(const FabricTile& tile) {
  return {{"yarn_curves", tile.curves.size()},
          {"triangles", tile.mesh.triangle_count()},
          {"vertices", tile.mesh.positions.size()},
          {"materials", tile.materials.size()},
          {"z_min", tile.z_min},
          {"z_max", tile.z_max}};
}

// A build's figures (FabricAsset::Figures), a line per level.
void PrintLevels(const nlohmann::json& figures) {
  for (const nlohmann::json& level : figures.at("levels")) {
    std::printf("  level %d (%d²)", level.at("level").get<int>(), level.at("resolution").get<int>());
    if (level.contains("relative_rmse")) {
      std::printf(": relative RMSE %.2f%%", 100.0 * level.at("relative_rmse").get<double>());
    }
    if (level.contains("lm_iterations_per_texel")) {
      std::printf(", %.1f LM iterations/texel, %d fallbacks, %d empty",
                  level.at("lm_iterations_per_texel").get<double>(),
                  level.at("fallback_fewer_lobes").get<int>() + level.at("fallback_diffuse").get<int>(),
                  level.at("empty").get<int>());
    }
    std::printf("\n");
  }
}

// levelN_density.png per level, and level0_vrf.png: the finest level's diffuse VRF for
// every light direction side by side (longitude across, altitude up), empty voxels black.
void WriteLumisliceImages(const Lumislice& slice, const std::filesystem::path& directory) {
  std::filesystem::create_directories(directory);
  const float peak = 1.0f - kFibreDensityEpsilon;
  for (size_t l = 0; l < slice.levels.size(); ++l) {
    const LumisliceLevel& level = slice.levels[l];
    Image image(level.resolution, level.resolution, 3);
    for (int y = 0; y < level.resolution; ++y) {
      for (int x = 0; x < level.resolution; ++x) {
        const float value = level.density[static_cast<size_t>(level.resolution - 1 - y) * level.resolution + x];
        for (int c = 0; c < 3; ++c) image.at(x, y, c) = value / peak;
      }
    }
    WriteImage(image, directory / ("level" + std::to_string(l) + "_density.png"));
  }
  const LumisliceLevel& finest = slice.levels.front();
  const int side = finest.resolution;
  Image vrf(side * kLumisliceLongitudes, side * kLumisliceAltitudes, 3);
  for (int d = 0; d < kLumisliceDirections; ++d) {
    const int column = d % kLumisliceLongitudes, row = kLumisliceAltitudes - 1 - d / kLumisliceLongitudes;
    for (int y = 0; y < side; ++y) {
      for (int x = 0; x < side; ++x) {
        const size_t voxel = static_cast<size_t>(side - 1 - y) * side + x;
        const glm::vec4 value = finest.density[voxel] > 0.0f ? finest.at(d, voxel) : glm::vec4(0.0f);
        for (int c = 0; c < 3; ++c) vrf.at(column * side + x, row * side + y, c) = value[c];
      }
    }
  }
  WriteImage(vrf, directory / "level0_vrf.png");
}

// The fabric's yarn `index` (--yarn), or an error saying how many it has.
const v1::YarnSpec& YarnAt(const v1::FabricSpec& fabric, int index) {
  if (index >= fabric.yarns_size()) {
    throw Error(ErrorCode::kInvalidArgument,
                "--yarn " + std::to_string(index) + ": the fabric has " + std::to_string(fabric.yarns_size()) + " yarns");
  }
  return fabric.yarns(index);
}

uintmax_t DirectoryBytes(const std::filesystem::path& directory) {
  uintmax_t bytes = 0;
  for (const auto& entry : std::filesystem::directory_iterator(directory)) {
    if (entry.is_regular_file()) bytes += entry.file_size();
  }
  return bytes;
}

}  // namespace

void FabricInput::AddTo(CLI::App* command) {
  command->add_option("fabric", fabric, "Fabric spec file (JSON)")->required();
  command->add_option("--settings", settings, "Precompute settings file (JSON); defaults if absent");
}

v1::FabricSpec FabricInput::LoadFabric() const { return LoadSpecFile<v1::FabricSpec>(fabric, "fabric"); }

v1::PrecomputeSettings LoadSettingsFile(const std::string& path) {
  return path.empty() ? v1::PrecomputeSettings() : LoadSpecFile<v1::PrecomputeSettings>(path, "precompute");
}

v1::PrecomputeSettings FabricInput::LoadSettings() const { return LoadSettingsFile(settings); }

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
            const Stopwatch stopwatch;
            const FabricTile tile = BuildFabricTile(LoadSpecFile<v1::FabricSpec>(options->fabric, "fabric"));
            const double build_seconds = stopwatch.Seconds();
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

LabCommand AddYarnSectionCommand(CLI::App& app, const LabFlags& flags) {
  struct Options {
    std::string fabric, out;
    int yarn = 0;
    int resolution = 64;
  };
  auto options = std::make_shared<Options>();
  auto* command = app.add_subcommand(
      "yarn-section", "Write a yarn's cross-section fibre density (plies, fuzz; docs/lumislice.md) as an image");
  command->add_option("fabric", options->fabric, "Fabric spec file (JSON)")->required();
  command->add_option("--yarn", options->yarn, "Index into the fabric's yarns")->check(CLI::Range(0, kMaxYarns - 1));
  command->add_option("--resolution", options->resolution, "Cells a side")->check(CLI::Range(4, 1024));
  command->add_option("--out,-o", options->out, "Output image: .exr the density, .png it over its peak")->required();
  return {command, [&flags, options] {
            const v1::FabricSpec fabric = WithDefaults(LoadSpecFile<v1::FabricSpec>(options->fabric, "fabric"));
            ThrowIfAny(Validate(fabric));
            const YarnSection section = MakeYarnSection(YarnAt(fabric, options->yarn));
            const int side = options->resolution;
            const std::vector<float> density = SectionDensityGrid(section, side);
            const bool png = FormatFromPath(options->out) == ImageFileFormat::kPng;
            const float peak = 1.0f - kFibreDensityEpsilon;
            Image image(side, side, 3);
            double fibres = 0.0;
            for (int y = 0; y < side; ++y) {
              for (int x = 0; x < side; ++x) {
                const float value = density[static_cast<size_t>(side - 1 - y) * side + x];  // +y up
                for (int c = 0; c < 3; ++c) image.at(x, y, c) = png ? value / peak : value;
                fibres += value;
              }
            }
            WriteImage(image, options->out);
            const double cell = 2.0 * section.extent() / side;
            if (flags.json) {
              PrintJson({{"out", options->out},
                         {"plies", section.plies},
                         {"ply_radius", section.ply_radius},
                         {"ply_offset", section.ply_offset},
                         {"extent", section.extent()},
                         {"fibre_area", fibres * cell * cell}});
            } else {
              std::printf("wrote %s: %u plies of %.3f yarn radii at %.3f from the centre, %.2f yarn radii across; "
                          "fibre area %.3f (yarn radii squared)\n",
                          options->out.c_str(), section.plies, section.ply_radius, section.ply_offset,
                          2.0 * section.extent(), fibres * cell * cell);
            }
            return 0;
          }};
}

LabCommand AddLumisliceCommand(CLI::App& app, const LabFlags& flags) {
  struct Options {
    std::string fabric, out;
    int yarn = 0;
    LumisliceSettings settings;
  };
  auto options = std::make_shared<Options>();
  auto* command = app.add_subcommand(
      "lumislice", "Build a yarn's lumislice, every level (docs/lumislice.md), and write its tables as images");
  command->add_option("fabric", options->fabric, "Fabric spec file (JSON)")->required();
  command->add_option("--yarn", options->yarn, "Index into the fabric's yarns")->check(CLI::Range(0, kMaxYarns - 1));
  command->add_option("--resolution", options->settings.resolution, "Voxels a side of the finest level");
  command->add_option("--out,-o", options->out,
                      "Output directory: levelN_density.png (over its peak) and level0_vrf.png (the diffuse VRF of "
                      "every light direction, longitude across, altitude up)");
  return {command, [&flags, options] {
            const v1::FabricSpec fabric = WithDefaults(LoadSpecFile<v1::FabricSpec>(options->fabric, "fabric"));
            ThrowIfAny(Validate(fabric));
            const v1::YarnSpec& yarn = YarnAt(fabric, options->yarn);
            const Stopwatch stopwatch;
            Lumislice slice;
            {
              ProgressBar bar("lumislice");
              slice = BuildLumislice(MakeYarnSection(yarn), MakeYarnMaterial(yarn), options->settings,
                                     [&](double fraction) { bar.Update(fraction, "light directions"); });
            }
            const double seconds = stopwatch.Seconds();
            if (!options->out.empty()) WriteLumisliceImages(slice, options->out);
            if (flags.json) {
              nlohmann::json levels = nlohmann::json::array();
              for (const LumisliceLevel& level : slice.levels) {
                levels.push_back({{"resolution", level.resolution}, {"voxel", level.voxel}});
              }
              PrintJson({{"seconds", seconds}, {"bytes", slice.StoredBytes()}, {"levels", levels}});
            } else {
              std::printf("lumislice of yarn %d: %zu levels (%d² down to 1²), %d light directions, built in %.2f s, "
                          "%.2f MB as half floats\n",
                          options->yarn, slice.levels.size(), slice.levels.front().resolution, kLumisliceDirections,
                          seconds, slice.StoredBytes() / 1e6);
            }
            return 0;
          }};
}

LabCommand AddAcquireCommand(CLI::App& app, const LabFlags& flags) {
  struct Options {
    FabricInput input;
    std::string out;
    unsigned threads = 0;
  };
  auto options = std::make_shared<Options>();
  auto* command = app.add_subcommand(
      "acquire", "Render a fabric's radiance samples (views × lights per texel) into a samples file");
  options->input.AddTo(command);
  command->add_option("--out,-o", options->out, "Output samples file (format: core/acquire/radiance_samples.h)")
      ->required();
  command->add_option("--threads", options->threads, "Worker threads (0 = every core)");
  return {command, [&flags, options] {
            const auto fabric = options->input.LoadFabric();
            const auto settings = options->input.LoadSettings();
            const Stopwatch stopwatch;
            const FabricTile tile = BuildFabricTile(fabric);
            const double geometry_seconds = stopwatch.Seconds();
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

LabCommand AddFitCommand(CLI::App& app, const LabFlags& flags) {
  struct Options {
    std::string samples, settings;
  };
  auto options = std::make_shared<Options>();
  auto* command = app.add_subcommand(
      "fit", "Build the settings' method's asset from a samples file written by acquire (the fit, the "
             "factorisation, the training) and print its figures; times the build alone, writes no asset");
  command->add_option("samples", options->samples, "Samples file (from loom-lab acquire)")->required();
  command->add_option("--settings", options->settings, "Precompute settings file (JSON); defaults if absent");
  return {command, [&flags, options] {
            const v1::PrecomputeSettings settings = WithDefaults(LoadSettingsFile(options->settings));
            const RadianceSamples samples = ReadRadianceSamples(options->samples);
            const FabricMethod& method = MethodOf(settings.method());
            std::unique_ptr<FabricAsset> asset;
            {
              ProgressBar bar(std::string(method.name()));
              asset = method.Build(samples, settings,
                                   [&bar](double f, std::string_view stage) { bar.Update(f, stage); });
            }
            const nlohmann::json figures = asset->Figures();
            if (flags.json) {
              PrintJson(figures);
            } else {
              std::printf("built %s from %s in %.2f s (%zu levels)\n", std::string(method.name()).c_str(),
                          options->samples.c_str(), asset->build_seconds(), figures.at("levels").size());
              PrintLevels(figures);
              if (asset->colour_channels()) {
                std::printf("colour components in %zu sheets: the key leaves the yarns' albedos out, so a fabric that "
                            "differs only in them renders from this asset\n",
                            asset->colour_sheets().size() + 1);
              }
            }
            return 0;
          }};
}

LabCommand AddPrecomputeCommand(CLI::App& app, const LabFlags& flags) {
  struct Options {
    FabricInput input;
    std::string out;
  };
  auto options = std::make_shared<Options>();
  auto* command = app.add_subcommand(
      "precompute", "Geometry → acquisition → the settings' method's build → its fabric asset (as cached) in a directory");
  options->input.AddTo(command);
  command->add_option("--out,-o", options->out, "Output directory (the method's files and manifest.json)")
      ->required();
  return {command, [&flags, options] {
            const auto fabric = options->input.LoadFabric();
            const auto settings = options->input.LoadSettings();
            const Stopwatch stopwatch;
            PrecomputeStats stats;
            std::unique_ptr<FabricAsset> asset;
            {
              ProgressBar bar("precompute");
              asset = PrecomputeAsset(fabric, settings, [&bar](double f, std::string_view stage) { bar.Update(f, stage); },
                                      &stats);
            }
            const std::string key = FabricKey(fabric, settings);
            asset->Write(settings, key, options->out);
            const nlohmann::json figures = asset->Figures();
            const double total_seconds = stopwatch.Seconds();
            const uintmax_t asset_bytes = DirectoryBytes(options->out);
            if (flags.json) {
              PrintJson({{"key", key},
                         {"out", options->out},
                         {"asset_bytes", asset_bytes},
                         {"seconds", total_seconds},
                         {"geometry_seconds", stats.geometry_seconds},
                         {"tile_triangles", stats.tile_triangles},
                         {"acquisition",
                          {{"seconds", stats.acquisition.seconds},
                           {"rays", stats.acquisition.rays},
                           {"rays_per_second", stats.acquisition.rays_per_second()},
                           {"mean_alpha", stats.mean_alpha}}},
                         {"build", figures},
                         {"colour_sheets", asset->colour_channels() ? asset->colour_sheets().size() + 1 : 0}});
            } else {
              std::printf("wrote %s (%.1f KB): acquisition %.1f s, %s %.1f s (%zu levels), total %.1f s\nkey %s\n",
                          options->out.c_str(), static_cast<double>(asset_bytes) / 1024.0, stats.acquisition.seconds,
                          std::string(asset->method().name()).c_str(), asset->build_seconds(),
                          figures.at("levels").size(), total_seconds, key.c_str());
              PrintLevels(figures);
              if (asset->colour_channels()) {
                std::printf("colour components in %zu sheets: the key leaves the yarns' albedos out, so a fabric that "
                            "differs only in them renders from this asset\n",
                            asset->colour_sheets().size() + 1);
              }
            }
            return 0;
          }};
}

}  // namespace loom::lab
