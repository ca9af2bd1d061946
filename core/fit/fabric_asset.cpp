#include "core/fit/fabric_asset.h"

#include <algorithm>
#include <cmath>

#include <nlohmann/json.hpp>

#include "core/acquire/hemisphere_directions.h"
#include "core/methods/asset_files.h"
#include "core/spec/defaults.h"
#include "core/spec/limits.h"
#include "core/spec/spec_json.h"
#include "core/util/error.h"
#include "core/util/file_io.h"
#include "core/util/sha256.h"

namespace loom {
namespace {

using nlohmann::json;

constexpr const char* kParametersFile = "parameters.exr";
constexpr const char* kLutFile = "lut.exr";
constexpr const char* kManifestFile = "manifest.json";

// A lobe's peak is a^N with a = Σ C_k l'_k v'_k: a relative error ε in a becomes
// N·ε in the BRDF, 12 % at N = 256 (a near-mirror lobe) for half floats' ε = 2^-11.
// The lobe coefficients and the frame that l' and v' are taken in (normal,
// tangent) stay 32-bit; ρ, N, the table and alpha enter linearly (or, for N,
// through ln a ≈ 0 at such peaks) and lose ≤ 0.1 % in half floats.
bool NeedsFullFloat(const std::string& channel) {
  for (const char* part : {".Cx.", ".Cy.", ".Cz.", "normal.", "tangent."}) {
    if (channel.find(part) != std::string::npos) return true;
  }
  return false;
}

std::vector<std::string> ParameterChannelNames(uint32_t lobes) {
  std::vector<std::string> names;
  auto rgb = [&](const std::string& base) {
    for (const char* c : {"R", "G", "B"}) names.push_back(base + "." + c);
  };
  rgb("rho");
  for (uint32_t i = 0; i < lobes; ++i) {
    for (const char* p : {"Cx", "Cy", "Cz", "N"}) rgb("lobe" + std::to_string(i) + "." + p);
  }
  for (const char* c : {"X", "Y", "Z"}) names.push_back(std::string("normal.") + c);
  for (const char* c : {"X", "Y", "Z"}) names.push_back(std::string("tangent.") + c);
  names.push_back("rmse");
  names.push_back("status");
  return names;
}

// The per-texel values in ParameterChannelNames order, for writing and reading
// through one list (so the two cannot disagree).
template <typename Level, typename Visit>
void ForEachParameter(Level& level, size_t texel, uint32_t lobes, Visit visit) {
  auto& brdf = level.brdfs[texel];
  for (int c = 0; c < 3; ++c) visit(brdf.rho[c]);
  for (uint32_t i = 0; i < lobes; ++i) {
    for (auto* p : {&brdf.lobes[i].cx, &brdf.lobes[i].cy, &brdf.lobes[i].cz, &brdf.lobes[i].n}) {
      for (int c = 0; c < 3; ++c) visit((*p)[c]);
    }
  }
  for (int c = 0; c < 3; ++c) visit(level.normals[texel][c]);
  for (int c = 0; c < 3; ++c) visit(level.tangents[texel][c]);
  visit(level.rmse[texel]);
}

LevelImage ParameterImage(const FittedFabric& fabric) {
  LevelImage image{ParameterChannelNames(fabric.lobes), {}, {}};
  for (size_t c = 0; c < image.channel_names.size(); ++c) image.keep_float[c] = NeedsFullFloat(image.channel_names[c]);
  for (const FittedLevel& level : fabric.levels) {
    std::vector<float>& pixels = image.pixels.emplace_back();
    for (size_t texel = 0; texel < level.brdfs.size(); ++texel) {
      ForEachParameter(level, texel, fabric.lobes, [&](float value) { pixels.push_back(value); });
      pixels.push_back(static_cast<float>(level.status[texel]));
    }
    image.sides.push_back(static_cast<int>(level.resolution));
  }
  return image;
}

LevelImage LutImage(const FittedFabric& fabric) {
  const size_t views = fabric.view_directions.size();
  const uint32_t k = HemisphereGridSide(static_cast<uint32_t>(views));
  LevelImage image{{"R", "G", "B", "A"}, {}, {}};
  for (const FittedLevel& level : fabric.levels) {
    const size_t side = size_t{level.resolution} * k;
    std::vector<float>& pixels = image.pixels.emplace_back(side * side * 4);
    for (size_t texel = 0; texel < level.brdfs.size(); ++texel) {
      for (size_t v = 0; v < views; ++v) {
        float* pixel = &pixels[DirectionAtlasPixel(texel, level.resolution, v, k) * 4];
        const glm::vec3 t = level.lut[texel * views + v];
        pixel[0] = t.r;
        pixel[1] = t.g;
        pixel[2] = t.b;
        pixel[3] = level.alpha[texel * views + v];
      }
    }
    image.sides.push_back(static_cast<int>(side));
  }
  return image;
}

json StatsJson(const FitLevelStats& s) {
  return {{"level", s.level},
          {"resolution", s.resolution},
          {"samples", s.samples},
          {"rmse_mean", s.rmse_mean},
          {"rmse_p95", s.rmse_p95},
          {"rmse_max", s.rmse_max},
          {"relative_rmse", s.relative_rmse},
          {"black", s.black},
          {"fallback_fewer_lobes", s.fewer_lobes},
          {"fallback_diffuse", s.diffuse_only},
          {"empty_texels", s.empty},
          {"lm_iterations_per_texel", s.lm_iterations_per_texel},
          {"mean_alternations", s.mean_alternations},
          {"fit_seconds", s.fit_seconds}};
}

FitLevelStats StatsFromJson(const json& j) {
  FitLevelStats s;
  s.level = j.at("level");
  s.resolution = j.at("resolution");
  s.samples = j.at("samples");
  s.rmse_mean = j.at("rmse_mean");
  s.rmse_p95 = j.at("rmse_p95");
  s.rmse_max = j.at("rmse_max");
  s.relative_rmse = j.at("relative_rmse");
  s.black = j.at("black");
  s.fewer_lobes = j.at("fallback_fewer_lobes");
  s.diffuse_only = j.at("fallback_diffuse");
  s.empty = j.at("empty_texels");
  s.lm_iterations_per_texel = j.at("lm_iterations_per_texel");
  s.mean_alternations = j.at("mean_alternations");
  s.fit_seconds = j.at("fit_seconds");
  return s;
}

}  // namespace

void WriteFabricAsset(const FittedFabric& fabric, const v1::PrecomputeSettings& settings,
                      const std::string& fabric_key, const AssetSheet& directory) {
  const v1::PrecomputeSettings resolved = WithDefaults(settings);
  const bool half = resolved.half_float();
  std::filesystem::create_directories(directory.directory);
  const std::string parameters_sha = WriteLevelImage(ParameterImage(fabric), directory / kParametersFile, half);
  const std::string lut_sha = WriteLevelImage(LutImage(fabric), directory / kLutFile, half);

  json levels = json::array();
  for (const FittedLevel& level : fabric.levels) levels.push_back(StatsJson(level.stats));
  const json manifest = {
      {"method", "svbrdf"},
      {"asset_version", kAssetFormatVersion},
      {"fabric_key", fabric_key},
      {"settings", json::parse(SpecToJson(resolved, false))},
      {"lobes", fabric.lobes},
      {"lookup_table", fabric.lookup_table},
      {"view_heights", fabric.view_heights},
      {"half_float", half},
      {"resolution", fabric.levels.front().resolution},
      {"view_directions", fabric.view_directions.size()},
      {"fitted_levels", fabric.levels.size()},
      {"levels", levels},
      {"fit_seconds", fabric.seconds},
      {"files",
       {{kParametersFile, FileEntry(directory / kParametersFile, parameters_sha)},
        {kLutFile, FileEntry(directory / kLutFile, lut_sha)}}},
  };
  WriteFileAtomic(directory / kManifestFile, manifest.dump(2) + "\n");
}

FittedFabric ReadFabricAsset(const AssetSheet& directory) {
  const std::filesystem::path manifest_path = directory / kManifestFile;
  json manifest;
  try {
    manifest = json::parse(ReadFile(manifest_path));
    if (manifest.at("asset_version").get<uint32_t>() != kAssetFormatVersion) {
      throw Error(ErrorCode::kInvalidArgument, manifest_path.string() + " has asset version " +
                                                   manifest.at("asset_version").dump() + ", this engine reads " +
                                                   std::to_string(kAssetFormatVersion));
    }
    FittedFabric fabric;
    const auto invalid = [&manifest_path](const std::string& what) {
      return Error(ErrorCode::kInvalidArgument, manifest_path.string() + ": " + what);
    };
    const auto lobes = manifest.at("lobes").get<int64_t>();
    if (lobes < kMinLobes || lobes > kMaxLobes) {
      throw invalid("lobes " + std::to_string(lobes) + " is not in [" + std::to_string(kMinLobes) + ", " +
                    std::to_string(kMaxLobes) + "]");
    }
    const auto view_count = manifest.at("view_directions").get<int64_t>();
    if (view_count < kMinDirections || view_count > kMaxDirections) {
      throw invalid("view_directions " + std::to_string(view_count) + " is not in [" +
                    std::to_string(kMinDirections) + ", " + std::to_string(kMaxDirections) + "]");
    }
    // No more LUT texels than the radiance-sample cap allows.
    CheckLevelChain(manifest.at("levels"), static_cast<uint64_t>(view_count), kMaxRadianceSamples / kMinDirections,
                    invalid);
    fabric.lobes = static_cast<uint32_t>(lobes);
    fabric.lookup_table = manifest.at("lookup_table");
    fabric.seconds = manifest.at("fit_seconds");
    fabric.view_directions = HemisphereGridDirections(static_cast<uint32_t>(view_count));
    const size_t views = fabric.view_directions.size();
    fabric.view_heights = ManifestViewHeights(manifest, views, invalid);
    const int k = static_cast<int>(HemisphereGridSide(static_cast<uint32_t>(views)));
    const int side = manifest.at("levels")[0].at("resolution").get<int>();
    const json& files = manifest.at("files");
    const std::filesystem::path parameters_path = VerifiedFile(directory, files, kParametersFile, side);
    const std::filesystem::path lut_path = VerifiedFile(directory, files, kLutFile, side * k);
    std::vector<int> parameter_sides, lut_sides;
    for (const json& stats : manifest.at("levels")) {
      FittedLevel& level = fabric.levels.emplace_back();
      level.stats = StatsFromJson(stats);
      level.resolution = level.stats.resolution;
      const size_t texels = size_t{level.resolution} * level.resolution;
      level.brdfs.assign(texels, LafortuneBrdf{.lobe_count = fabric.lobes});
      level.normals.resize(texels);
      level.tangents.resize(texels);
      level.rmse.resize(texels);
      level.status.resize(texels);
      level.lut.resize(texels * views);
      level.alpha.resize(texels * views);
      parameter_sides.push_back(static_cast<int>(level.resolution));
      lut_sides.push_back(static_cast<int>(level.resolution) * k);
    }
    const auto parameters = ReadLevelImage(parameters_path, parameter_sides, ParameterChannelNames(fabric.lobes));
    const auto luts = ReadLevelImage(lut_path, lut_sides, {"R", "G", "B", "A"});
    for (size_t j = 0; j < fabric.levels.size(); ++j) {
      FittedLevel& level = fabric.levels[j];
      const float* value = parameters[j].data();
      for (size_t texel = 0; texel < level.brdfs.size(); ++texel) {
        ForEachParameter(level, texel, fabric.lobes, [&](float& out) { out = *value++; });
        const float status = *value++;
        if (!(status >= 0.0f && status <= static_cast<float>(TexelFitStatus::kEmpty) && status == std::floor(status))) {
          throw invalid("parameters.exr level " + std::to_string(j) + " texel " + std::to_string(texel) +
                        ": status " + std::to_string(status) + " is not a TexelFitStatus");
        }
        level.status[texel] = static_cast<TexelFitStatus>(static_cast<int>(status));
      }
      if (!std::all_of(parameters[j].begin(), parameters[j].end(), [](float v) { return std::isfinite(v); }) ||
          !std::all_of(luts[j].begin(), luts[j].end(), [](float v) { return std::isfinite(v); })) {
        throw invalid("level " + std::to_string(j) + " holds a non-finite number");
      }
      for (size_t texel = 0; texel < level.brdfs.size(); ++texel) {
        for (size_t v = 0; v < views; ++v) {
          const float* pixel = &luts[j][DirectionAtlasPixel(texel, level.resolution, v, static_cast<uint32_t>(k)) * 4];
          level.lut[texel * views + v] = glm::vec3(pixel[0], pixel[1], pixel[2]);
          level.alpha[texel * views + v] = pixel[3];
        }
      }
    }
    return fabric;
  } catch (const json::exception& e) {
    throw Error(ErrorCode::kInvalidArgument, manifest_path.string() + " is not a valid manifest: " + e.what());
  }
}

}  // namespace loom
