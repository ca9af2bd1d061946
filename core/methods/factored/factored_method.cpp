#include "core/methods/factored/factored_method.h"

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

constexpr const char* kViewTermsFile = "view_terms.exr";
constexpr const char* kLightTermsFile = "light_terms.exr";
constexpr const char* kViewsFile = "views.exr";
constexpr const char* kManifestFile = "manifest.json";
// 1: the first layout. 2: view-depth sampling planes. 3: the shape's terms, one
// channel each, times the table's ambient response. 4: acquisition shades a facet
// facing the view even where the shading normal does not.
constexpr uint32_t kFactoredFormatVersion = 4;

// Terms first … first + channels − 1 of one level over one grid (`count` stored
// directions) as one direction atlas of `channels` channels, zeros past the rank.
// `terms` is [(texel·K + k)·count + d].
std::vector<float> TermAtlas(const std::vector<float>& terms, uint32_t rank, uint32_t resolution, size_t count,
                             uint32_t first, uint32_t channels) {
  const uint32_t k = GridSide(count);
  const size_t texels = size_t{resolution} * resolution;
  std::vector<float> atlas(texels * count * channels, 0.0f);
  for (size_t texel = 0; texel < texels; ++texel) {
    for (uint32_t term = first; term < std::min(rank, first + channels); ++term) {
      for (size_t d = 0; d < count; ++d) {
        atlas[DirectionAtlasPixel(texel, resolution, d, k) * channels + term - first] =
            terms[(texel * rank + term) * count + d];
      }
    }
  }
  return atlas;
}

// The GPU's layers: four terms to an RGBA layer.
uint32_t TermLayerCount(uint32_t rank) { return (rank + 3) / 4; }

std::vector<std::string> TermChannels(char name, uint32_t rank) {
  std::vector<std::string> channels;
  for (uint32_t term = 0; term < rank; ++term) channels.push_back(name + std::to_string(term));
  return channels;
}

// One image of every level's terms over one grid, a channel per term.
template <typename Terms>
LevelImage TermImage(const FactoredFabric& fabric, char name, size_t count, const Terms& terms_of) {
  LevelImage image{TermChannels(name, fabric.rank), {}, {}};
  for (const FactoredLevel& level : fabric.levels) {
    image.pixels.push_back(TermAtlas(terms_of(level), fabric.rank, level.resolution, count, 0, fabric.rank));
    image.sides.push_back(static_cast<int>(level.resolution * GridSide(count)));
  }
  return image;
}

// The inverse of TermImage for one level's pixels.
std::vector<float> TermsFromImage(const std::vector<float>& pixels, uint32_t rank, uint32_t resolution, size_t count) {
  const uint32_t k = GridSide(count);
  const size_t texels = size_t{resolution} * resolution;
  std::vector<float> terms(texels * rank * count);
  for (size_t texel = 0; texel < texels; ++texel) {
    for (uint32_t term = 0; term < rank; ++term) {
      for (size_t d = 0; d < count; ++d) {
        terms[(texel * rank + term) * count + d] = pixels[DirectionAtlasPixel(texel, resolution, d, k) * rank + term];
      }
    }
  }
  return terms;
}

class FactoredTextures final : public GpuFabric {
 public:
  FactoredTextures(const FactoredFabric& fabric, bool half)
      : surface_{static_cast<int>(fabric.levels.size()), static_cast<int>(fabric.levels.at(0).resolution),
                 static_cast<int>(GridSide(fabric.view_count())), static_cast<int>(GridSide(fabric.light_count())),
                 fabric.view_heights},
        views_(surface_.levels(), surface_.resolution() * surface_.view_side(), 4, half),
        terms_(fabric, half) {
    for (int level = 0; level < surface_.levels(); ++level) {
      const FactoredLevel& data = fabric.levels[static_cast<size_t>(level)];
      views_.Upload(level, AmbientAlphaAtlas(data.ambient, data.alpha, data.resolution, fabric.view_count()).data());
    }
  }

  const FabricMethod& method() const override { return FactoredMethod(); }

  void Bind(const gl::ShaderProgram& program, int first_unit, glm::vec2 repeat) const override {
    surface_.Bind(program, views_.id(), first_unit, repeat);
    terms_.Bind(program, first_unit + FabricSurface::kUnits);
  }

  std::string ShaderDefines() const override { return terms_.ShaderDefines(); }

 private:
  FabricSurface surface_;
  LevelTexture views_;
  FactoredTermTextures terms_;
};

FactoredFabric ReadFactored(const AssetSheet& directory) {
  const std::filesystem::path manifest_path = directory / kManifestFile;
  const auto invalid = [&manifest_path](const std::string& what) {
    return Error(ErrorCode::kInvalidArgument, manifest_path.string() + ": " + what);
  };
  try {
    const json manifest = json::parse(ReadFile(manifest_path));
    const TableAssetHeader header = CheckTableManifest(manifest, "factored", kFactoredFormatVersion, invalid);
    const uint32_t views = header.views, lights = header.lights;
    FactoredFabric fabric;
    const auto rank = manifest.at("rank").get<int64_t>();
    if (rank < 1 || rank > kMaxFactoredRank) {
      throw invalid("rank " + std::to_string(rank) + " is not in [1, " + std::to_string(kMaxFactoredRank) + "]");
    }
    fabric.rank = static_cast<uint32_t>(rank);
    CheckLevelChain(manifest.at("levels"), uint64_t{views + lights} * fabric.rank,
                    kMaxRadianceSamples / kMinDirections, invalid);
    fabric.view_directions = HemisphereGridDirections(views);
    fabric.light_directions = HemisphereGridDirections(lights);
    fabric.view_heights = header.view_heights;
    fabric.seconds = header.build_seconds;
    std::vector<int> view_sides;
    for (const json& entry : manifest.at("levels")) {
      FactoredLevel& level = fabric.levels.emplace_back();
      level.resolution = entry.at("resolution");
      level.relative_rmse = entry.at("relative_rmse");
      view_sides.push_back(static_cast<int>(level.resolution * GridSide(views)));
    }
    const json& files = manifest.at("files");
    ReadFactoredTerms(directory, files, fabric, invalid);
    const auto atlases = ReadLevelImage(VerifiedFile(directory, files, kViewsFile, view_sides[0]), view_sides,
                                        {"R", "G", "B", "A"});
    for (size_t j = 0; j < fabric.levels.size(); ++j) {
      FactoredLevel& level = fabric.levels[j];
      ReadAmbientAlphaAtlas(atlases[j], level.resolution, views, level.ambient, level.alpha, invalid);
    }
    return fabric;
  } catch (const json::exception& e) {
    throw Error(ErrorCode::kInvalidArgument, manifest_path.string() + " is not a valid manifest: " + e.what());
  }
}

class Factored final : public FabricMethod {
 public:
  v1::FabricMethod id() const override { return v1::FABRIC_METHOD_FACTORED; }
  std::string_view name() const override { return "factored"; }
  std::string_view cloth_shader() const override { return "factored_cloth.frag"; }
  uint32_t asset_format_version() const override { return kFactoredFormatVersion; }

  v1::PrecomputeSettings KeySettings(v1::PrecomputeSettings settings) const override {
    settings.clear_neural();
    return WithoutSvbrdfFit(std::move(settings));
  }

  std::string OwnSettings(const v1::PrecomputeSettings& settings) const override {
    return SpecToJson(settings.factored(), false);
  }

  std::unique_ptr<FabricAsset> Build(const RadianceSamples& samples,
                                     const v1::PrecomputeSettings& settings,
                                     const BuildProgress& progress) const override {
    if (progress) progress(0.0, "tabulate");
    const TabulatedFabric table =
        TabulateFabric(samples, settings.mip_levels() != v1::MIP_LEVELS_NONE);
    FactoredFabric fabric = FactorFabric(table, settings.factored().rank(), 0, [&progress](double fraction) {
      if (progress) progress(fraction, "factor");
    });
    fabric.seconds += table.seconds;
    return std::make_unique<FactoredAsset>(std::move(fabric));
  }

  std::unique_ptr<FabricAsset> Read(const AssetSheet& directory) const override {
    return std::make_unique<FactoredAsset>(ReadFactored(directory));
  }
};

}  // namespace

json WriteFactoredTerms(const FactoredFabric& fabric, const AssetSheet& directory, bool half) {
  const auto view_terms = [](const FactoredLevel& level) -> const std::vector<float>& { return level.view_terms; };
  const auto light_terms = [](const FactoredLevel& level) -> const std::vector<float>& { return level.light_terms; };
  const std::string a_sha =
      WriteLevelImage(TermImage(fabric, 'a', fabric.view_count(), view_terms), directory / kViewTermsFile, half);
  const std::string b_sha =
      WriteLevelImage(TermImage(fabric, 'b', fabric.light_count(), light_terms), directory / kLightTermsFile, half);
  return {{kViewTermsFile, FileEntry(directory / kViewTermsFile, a_sha)},
          {kLightTermsFile, FileEntry(directory / kLightTermsFile, b_sha)}};
}

void ReadFactoredTerms(const AssetSheet& directory, const json& files, FactoredFabric& fabric,
                       const std::function<Error(const std::string&)>& invalid) {
  const size_t views = fabric.view_count(), lights = fabric.light_count();
  std::vector<int> view_sides, light_sides;
  for (const FactoredLevel& level : fabric.levels) {
    view_sides.push_back(static_cast<int>(level.resolution * GridSide(views)));
    light_sides.push_back(static_cast<int>(level.resolution * GridSide(lights)));
  }
  const auto a = ReadLevelImage(VerifiedFile(directory, files, kViewTermsFile, view_sides.at(0)), view_sides,
                                TermChannels('a', fabric.rank));
  const auto b = ReadLevelImage(VerifiedFile(directory, files, kLightTermsFile, light_sides.at(0)), light_sides,
                                TermChannels('b', fabric.rank));
  for (size_t j = 0; j < fabric.levels.size(); ++j) {
    FactoredLevel& level = fabric.levels[j];
    const auto finite = [](float value) { return std::isfinite(value); };
    if (!std::all_of(a[j].begin(), a[j].end(), finite) || !std::all_of(b[j].begin(), b[j].end(), finite)) {
      throw invalid("level " + std::to_string(j) + " holds a non-finite term");
    }
    level.view_terms = TermsFromImage(a[j], fabric.rank, level.resolution, views);
    level.light_terms = TermsFromImage(b[j], fabric.rank, level.resolution, lights);
  }
}

FactoredTermTextures::FactoredTermTextures(const FactoredFabric& fabric, bool half)
    : rank_(fabric.rank),
      view_terms_(static_cast<int>(fabric.levels.size()),
                  static_cast<int>(fabric.levels.at(0).resolution * GridSide(fabric.view_count())), 4, half,
                  static_cast<int>(TermLayerCount(fabric.rank))),
      light_terms_(static_cast<int>(fabric.levels.size()),
                   static_cast<int>(fabric.levels.at(0).resolution * GridSide(fabric.light_count())), 4, half,
                   static_cast<int>(TermLayerCount(fabric.rank))) {
  for (size_t level = 0; level < fabric.levels.size(); ++level) {
    const FactoredLevel& data = fabric.levels[level];
    for (uint32_t layer = 0; layer < TermLayerCount(fabric.rank); ++layer) {
      const auto a = TermAtlas(data.view_terms, fabric.rank, data.resolution, fabric.view_count(), 4 * layer, 4);
      const auto b = TermAtlas(data.light_terms, fabric.rank, data.resolution, fabric.light_count(), 4 * layer, 4);
      view_terms_.Upload(static_cast<int>(level), a.data(), static_cast<int>(layer));
      light_terms_.Upload(static_cast<int>(level), b.data(), static_cast<int>(layer));
    }
  }
}

void FactoredTermTextures::Bind(const gl::ShaderProgram& program, int unit) const {
  glBindTextureUnit(static_cast<GLuint>(unit), view_terms_.id());
  glBindTextureUnit(static_cast<GLuint>(unit + 1), light_terms_.id());
  program.Set("u_fabric_view_terms", unit);
  program.Set("u_fabric_light_terms", unit + 1);
}

std::string FactoredTermTextures::ShaderDefines() const {
  return "#define LOOM_FACTORED_RANK " + std::to_string(rank_) + "\n";
}

const FabricMethod& FactoredAsset::method() const { return FactoredMethod(); }

void FactoredAsset::WriteSheet(const v1::PrecomputeSettings& settings, const std::string& fabric_key,
                               const AssetSheet& directory) const {
  const v1::PrecomputeSettings resolved = WithDefaults(settings);
  const bool half = resolved.half_float();
  std::filesystem::create_directories(directory.directory);
  json files = WriteFactoredTerms(fabric_, directory, half);
  const std::string views_sha =
      WriteLevelImage(AmbientAlphaImage(fabric_.levels, fabric_.view_count()), directory / kViewsFile, half);
  const TableAssetHeader header{static_cast<uint32_t>(fabric_.view_count()),
                                static_cast<uint32_t>(fabric_.light_count()), fabric_.levels.front().resolution,
                                fabric_.view_heights, fabric_.seconds};
  json manifest = TableManifest("factored", kFactoredFormatVersion, fabric_key, resolved, header,
                                Figures().at("levels"));
  manifest["rank"] = fabric_.rank;
  files[kViewsFile] = FileEntry(directory / kViewsFile, views_sha);
  manifest["files"] = files;
  WriteFileAtomic(directory / kManifestFile, manifest.dump(2) + "\n");
}

json FactoredAsset::Figures() const {
  json levels = json::array();
  for (size_t j = 0; j < fabric_.levels.size(); ++j) {
    levels.push_back({{"level", j},
                      {"resolution", fabric_.levels[j].resolution},
                      {"relative_rmse", fabric_.levels[j].relative_rmse}});
  }
  return {{"method", "factored"},
          {"seconds", fabric_.seconds},
          {"rank", fabric_.rank},
          {"view_directions", fabric_.view_count()},
          {"light_directions", fabric_.light_count()},
          {"levels", levels}};
}

std::vector<AssetPicture> FactoredAsset::Pictures() const {
  std::vector<AssetPicture> pictures;
  const size_t views = fabric_.view_count(), lights = fabric_.light_count(), rank = fabric_.rank;
  const size_t view = TopDirection(fabric_.view_directions), light = TopDirection(fabric_.light_directions);
  for (uint32_t j = 0; j < fabric_.levels.size(); ++j) {
    const FactoredLevel& level = fabric_.levels[j];
    pictures.push_back(AmbientPicture(j, level.resolution, level.ambient, views, view));
    if (rank > 0) {
      pictures.push_back({j, "view_term1", "view term a_1 seen from above, smallest to largest",
                          TexelPicture(
                              level.resolution,
                              [&](size_t texel) { return glm::vec3(level.view_terms[texel * rank * views + view]); },
                              PictureScale::kRange)});
      pictures.push_back(
          {j, "light_term1", "light term b_1 lit from above, smallest to largest",
           TexelPicture(
               level.resolution,
               [&](size_t texel) { return glm::vec3(level.light_terms[texel * rank * lights + light]); },
               PictureScale::kRange)});
    }
    pictures.push_back(CoveragePicture(j, level.resolution, level.alpha, views, view));
  }
  return pictures;
}

std::unique_ptr<GpuFabric> FactoredAsset::Upload(bool half) const {
  return std::make_unique<FactoredTextures>(fabric_, half);
}

const FabricMethod& FactoredMethod() {
  static const Factored method;
  return method;
}

}  // namespace loom
