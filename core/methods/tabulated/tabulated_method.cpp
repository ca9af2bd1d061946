#include "core/methods/tabulated/tabulated_method.h"

#include <GL/glcorearb.h>

#include <algorithm>
#include <cmath>

#include <nlohmann/json.hpp>

#include "core/acquire/hemisphere_directions.h"
#include "core/methods/asset_files.h"
#include "core/methods/direction_grid.h"
#include "core/methods/level_texture.h"
#include "core/methods/svbrdf/svbrdf_method.h"
#include "core/spec/defaults.h"
#include "core/spec/limits.h"
#include "core/spec/spec_json.h"
#include "core/util/error.h"
#include "core/util/file_io.h"

namespace loom {
namespace {

using nlohmann::json;

constexpr const char* kTableFile = "table.exr";
constexpr const char* kViewsFile = "views.exr";
constexpr const char* kManifestFile = "manifest.json";
// 1: the first layout. 2: view-depth sampling planes. 3: acquisition shades a facet
// facing the view even where the shading normal does not.
constexpr uint32_t kTabulatedFormatVersion = 3;

// The pixel of (texel, view, light) in a level's table atlas (tabulated_method.h):
// lights on a k_l×k_l block inside the view's cell of the texel's k×k block of views.
size_t TablePixel(size_t texel, uint32_t resolution, size_t view, size_t light, uint32_t k, uint32_t kl) {
  const size_t x = texel % resolution, y = texel / resolution, side = size_t{resolution} * k * kl;
  return ((y * k + view / k) * kl + light / kl) * side + (x * k + view % k) * kl + light % kl;
}

// Level `level`'s table atlas, RGB floats, row-major.
std::vector<float> TableAtlas(const TabulatedFabric& fabric, const TabulatedLevel& level) {
  const size_t views = fabric.view_count(), lights = fabric.light_count();
  const uint32_t k = GridSide(views), kl = GridSide(lights);
  const size_t side = size_t{level.resolution} * k * kl;
  std::vector<float> pixels(side * side * 3);
  for (size_t texel = 0; texel < level.texel_count(); ++texel) {
    for (size_t view = 0; view < views; ++view) {
      for (size_t light = 0; light < lights; ++light) {
        const glm::vec3 value = level.radiance[(texel * views + view) * lights + light];
        std::copy_n(&value[0], 3, &pixels[TablePixel(texel, level.resolution, view, light, k, kl) * 3]);
      }
    }
  }
  return pixels;
}

int TableSide(const TabulatedFabric& fabric, uint32_t resolution) {
  return static_cast<int>(resolution * GridSide(fabric.view_count()) * GridSide(fabric.light_count()));
}
int ViewsSide(const TabulatedFabric& fabric, uint32_t resolution) {
  return static_cast<int>(resolution * GridSide(fabric.view_count()));
}

// The two atlases of every level, as images.
LevelImage TableImage(const TabulatedFabric& fabric) {
  LevelImage image{{"R", "G", "B"}, {}, {}};
  for (const TabulatedLevel& level : fabric.levels) {
    image.pixels.push_back(TableAtlas(fabric, level));
    image.sides.push_back(TableSide(fabric, level.resolution));
  }
  return image;
}

class TabulatedTextures final : public GpuFabric {
 public:
  TabulatedTextures(const TabulatedFabric& fabric, bool half)
      : surface_{static_cast<int>(fabric.levels.size()), static_cast<int>(fabric.levels.at(0).resolution),
                 static_cast<int>(GridSide(fabric.view_count())), static_cast<int>(GridSide(fabric.light_count())),
                 fabric.view_heights},
        views_(surface_.levels(), ViewsSide(fabric, fabric.levels[0].resolution), 4, half),
        table_(surface_.levels(), TableSide(fabric, fabric.levels[0].resolution), 3, half) {
    for (int level = 0; level < surface_.levels(); ++level) {
      const TabulatedLevel& data = fabric.levels[static_cast<size_t>(level)];
      views_.Upload(level, AmbientAlphaAtlas(data.ambient, data.alpha, data.resolution, fabric.view_count()).data());
      table_.Upload(level, TableAtlas(fabric, data).data());
    }
  }

  const FabricMethod& method() const override { return TabulatedMethod(); }

  void Bind(const gl::ShaderProgram& program, int first_unit, glm::vec2 repeat) const override {
    glBindTextureUnit(static_cast<GLuint>(first_unit + FabricSurface::kUnits), table_.id());
    surface_.Bind(program, views_.id(), first_unit, repeat);
    program.Set("u_fabric_table", first_unit + FabricSurface::kUnits);
  }

 private:
  FabricSurface surface_;
  LevelTexture views_, table_;
};

TabulatedFabric ReadTabulated(const AssetSheet& directory) {
  const std::filesystem::path manifest_path = directory / kManifestFile;
  const auto invalid = [&manifest_path](const std::string& what) {
    return Error(ErrorCode::kInvalidArgument, manifest_path.string() + ": " + what);
  };
  try {
    const json manifest = json::parse(ReadFile(manifest_path));
    const TableAssetHeader header = CheckTableManifest(manifest, "tabulated", kTabulatedFormatVersion, invalid);
    const uint32_t views = header.views, lights = header.lights;
    CheckLevelChain(manifest.at("levels"), uint64_t{views} * lights, kMaxTabulatedSamples, invalid);
    TabulatedFabric fabric;
    fabric.view_directions = HemisphereGridDirections(views);
    fabric.light_directions = HemisphereGridDirections(lights);
    fabric.view_heights = header.view_heights;
    fabric.seconds = header.build_seconds;
    std::vector<int> table_sides, views_sides;
    for (const json& entry : manifest.at("levels")) {
      TabulatedLevel& level = fabric.levels.emplace_back();
      level.resolution = entry.at("resolution");
      table_sides.push_back(TableSide(fabric, level.resolution));
      views_sides.push_back(ViewsSide(fabric, level.resolution));
    }
    const json& files = manifest.at("files");
    const auto tables = ReadLevelImage(VerifiedFile(directory, files, kTableFile, table_sides[0]), table_sides,
                                       {"R", "G", "B"});
    const auto atlases = ReadLevelImage(VerifiedFile(directory, files, kViewsFile, views_sides[0]), views_sides,
                                        {"R", "G", "B", "A"});
    const uint32_t k = GridSide(views), kl = GridSide(lights);
    for (size_t j = 0; j < fabric.levels.size(); ++j) {
      TabulatedLevel& level = fabric.levels[j];
      const auto bad = [](float value) { return !(value >= 0.0f && std::isfinite(value)); };
      if (std::any_of(tables[j].begin(), tables[j].end(), bad)) {
        throw invalid("level " + std::to_string(j) + " holds a negative or non-finite number");
      }
      ReadAmbientAlphaAtlas(atlases[j], level.resolution, views, level.ambient, level.alpha, invalid);
      level.radiance.resize(level.texel_count() * views * lights);
      for (size_t texel = 0; texel < level.texel_count(); ++texel) {
        for (size_t view = 0; view < views; ++view) {
          for (size_t light = 0; light < lights; ++light) {
            const float* value = &tables[j][TablePixel(texel, level.resolution, view, light, k, kl) * 3];
            level.radiance[(texel * views + view) * lights + light] = glm::vec3(value[0], value[1], value[2]);
          }
        }
      }
    }
    return fabric;
  } catch (const json::exception& e) {
    throw Error(ErrorCode::kInvalidArgument, manifest_path.string() + " is not a valid manifest: " + e.what());
  }
}

class Tabulated final : public FabricMethod {
 public:
  v1::FabricMethod id() const override { return v1::FABRIC_METHOD_TABULATED; }
  std::string_view name() const override { return "tabulated"; }
  std::string_view cloth_shader() const override { return "tabulated_cloth.frag"; }
  uint32_t asset_format_version() const override { return kTabulatedFormatVersion; }

  v1::PrecomputeSettings KeySettings(v1::PrecomputeSettings settings) const override {
    settings.clear_factored();
    settings.clear_neural();
    return WithoutSvbrdfFit(std::move(settings));
  }

  std::unique_ptr<FabricAsset> Build(const RadianceSamples& samples,
                                     const v1::PrecomputeSettings& settings,
                                     const BuildProgress& progress) const override {
    if (progress) progress(0.0, "tabulate");
    auto asset = std::make_unique<TabulatedAsset>(
        TabulateFabric(samples, settings.mip_levels() != v1::MIP_LEVELS_NONE));
    if (progress) progress(1.0, "tabulate");
    return asset;
  }

  std::unique_ptr<FabricAsset> Read(const AssetSheet& directory) const override {
    return std::make_unique<TabulatedAsset>(ReadTabulated(directory));
  }
};

}  // namespace

const FabricMethod& TabulatedAsset::method() const { return TabulatedMethod(); }

void TabulatedAsset::WriteSheet(const v1::PrecomputeSettings& settings, const std::string& fabric_key,
                                const AssetSheet& directory) const {
  const v1::PrecomputeSettings resolved = WithDefaults(settings);
  const bool half = resolved.half_float();
  std::filesystem::create_directories(directory.directory);
  const std::string table_sha = WriteLevelImage(TableImage(fabric_), directory / kTableFile, half);
  const std::string views_sha = WriteLevelImage(AmbientAlphaImage(fabric_.levels, fabric_.view_count()), directory / kViewsFile, half);
  const TableAssetHeader header{static_cast<uint32_t>(fabric_.view_count()),
                                static_cast<uint32_t>(fabric_.light_count()), fabric_.levels.front().resolution,
                                fabric_.view_heights, fabric_.seconds};
  json manifest = TableManifest("tabulated", kTabulatedFormatVersion, fabric_key, resolved, header,
                                Figures().at("levels"));
  manifest["files"] = {{kTableFile, FileEntry(directory / kTableFile, table_sha)},
                       {kViewsFile, FileEntry(directory / kViewsFile, views_sha)}};
  WriteFileAtomic(directory / kManifestFile, manifest.dump(2) + "\n");
}

json TabulatedAsset::Figures() const {
  json levels = json::array();
  for (size_t j = 0; j < fabric_.levels.size(); ++j) {
    levels.push_back({{"level", j}, {"resolution", fabric_.levels[j].resolution}});
  }
  return {{"method", "tabulated"},
          {"seconds", fabric_.seconds},
          {"view_directions", fabric_.view_count()},
          {"light_directions", fabric_.light_count()},
          {"levels", levels}};
}

std::vector<AssetPicture> TabulatedAsset::Pictures() const {
  std::vector<AssetPicture> pictures;
  const size_t views = fabric_.view_count(), lights = fabric_.light_count();
  const size_t view = TopDirection(fabric_.view_directions), light = TopDirection(fabric_.light_directions);
  for (uint32_t j = 0; j < fabric_.levels.size(); ++j) {
    const TabulatedLevel& level = fabric_.levels[j];
    pictures.push_back(
        {j, "radiance", "radiance seen and lit from above, scaled to its maximum",
         TexelPicture(
             level.resolution, [&](size_t texel) { return level.radiance[(texel * views + view) * lights + light]; },
             PictureScale::kMaximum)});
    pictures.push_back(AmbientPicture(j, level.resolution, level.ambient, views, view));
    pictures.push_back(CoveragePicture(j, level.resolution, level.alpha, views, view));
  }
  return pictures;
}

std::unique_ptr<GpuFabric> TabulatedAsset::Upload(bool half) const {
  return std::make_unique<TabulatedTextures>(fabric_, half);
}

const FabricMethod& TabulatedMethod() {
  static const Tabulated method;
  return method;
}

}  // namespace loom
