#include "core/fit/fabric_asset.h"

#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cmath>

#include <nlohmann/json.hpp>

#include "core/acquire/hemisphere_directions.h"
#include "core/image/exr_header.h"
#include "core/spec/defaults.h"
#include "core/spec/limits.h"
#include "core/spec/spec_json.h"
#include "core/util/error.h"
#include "core/util/file_io.h"
#include "core/util/sha256.h"

namespace loom {
namespace {

namespace OIIO = OIIO_NAMESPACE;
using nlohmann::json;

constexpr const char* kParametersFile = "parameters.exr";
constexpr const char* kLutFile = "lut.exr";
constexpr const char* kManifestFile = "manifest.json";

// One image with its MIP levels, pixel-interleaved floats, level j of side sides[j].
// Channels flagged in `keep_float` stay 32-bit in a half-float file.
struct LevelImage {
  std::vector<std::string> channel_names;
  std::vector<int> sides;
  std::vector<std::vector<float>> pixels;
  std::vector<bool> keep_float = std::vector<bool>(channel_names.size(), false);
};

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
      const size_t x = texel % level.resolution, y = texel / level.resolution;
      for (size_t v = 0; v < views; ++v) {
        float* pixel = &pixels[((y * k + v / k) * side + x * k + v % k) * 4];
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

// Writes `image` to a temporary name beside `path`, then renames it; returns the
// file's SHA-256. Several levels become a tiled MIP-mapped OpenEXR, which must go
// down to 1×1: missing levels are point-sampled from the last fitted one.
std::string WriteLevelImage(const LevelImage& image, const std::filesystem::path& path, bool half) {
  const std::filesystem::path temp =
      path.parent_path() / (path.stem().string() + ".tmp-" + std::to_string(::getpid()) + ".exr");
  std::vector<int> sides = image.sides;
  std::vector<std::vector<float>> pixels = image.pixels;
  const int channels = static_cast<int>(image.channel_names.size());
  const bool mip = sides.size() > 1;
  while (mip && sides.back() > 1) {
    const int from = sides.back(), to = from / 2;
    std::vector<float> next(size_t(to) * to * channels);
    for (int y = 0; y < to; ++y) {
      for (int x = 0; x < to; ++x) {
        std::copy_n(&pixels.back()[(size_t(2 * y) * from + 2 * x) * channels], channels,
                    &next[(size_t(y) * to + x) * channels]);
      }
    }
    sides.push_back(to);
    pixels.push_back(std::move(next));
  }

  auto out = OIIO::ImageOutput::create(temp.string());
  if (!out) throw Error(ErrorCode::kInternal, "cannot create an OpenEXR writer: " + OIIO::geterror());
  for (size_t j = 0; j < sides.size(); ++j) {
    OIIO::ImageSpec spec(sides[j], sides[j], channels, half ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT);
    spec.channelnames = image.channel_names;
    if (half && std::find(image.keep_float.begin(), image.keep_float.end(), true) != image.keep_float.end()) {
      spec.format = OIIO::TypeDesc::FLOAT;  // OpenImageIO: the widest of the channel formats
      for (int c = 0; c < channels; ++c) {
        spec.channelformats.push_back(image.keep_float[c] ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::HALF);
      }
    }
    spec.attribute("compression", "zip");
    if (mip) {
      spec.tile_width = spec.tile_height = 32;
      spec.attribute("textureformat", "Plain Texture");  // OpenImageIO: MIP levels only for textures
      spec.attribute("openexr:roundingmode", 0);          // ROUND_DOWN: each level halves
    }
    const auto mode = j == 0 ? OIIO::ImageOutput::Create : OIIO::ImageOutput::AppendMIPLevel;
    if (!out->open(temp.string(), spec, mode) || !out->write_image(OIIO::TypeDesc::FLOAT, pixels[j].data())) {
      const std::string reason = out->geterror();
      std::filesystem::remove(temp);
      throw Error(ErrorCode::kInternal, "cannot write " + path.string() + ": " + reason);
    }
  }
  const bool closed = out->close();
  out.reset();  // the OpenEXR file is complete only once the writer is gone
  if (!closed) throw Error(ErrorCode::kInternal, "cannot write " + path.string() + ": " + OIIO::geterror());
  const std::string checksum = Sha256Hex(ReadFile(temp));
  std::filesystem::rename(temp, path);
  return checksum;
}

// The fitted levels of an image written by WriteLevelImage, channels in the order
// of `channels` (OpenEXR stores them sorted by name, so they are found by name).
std::vector<std::vector<float>> ReadLevelImage(const std::filesystem::path& path, const std::vector<int>& sides,
                                               const std::vector<std::string>& channels) {
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) throw Error(ErrorCode::kInvalidArgument, "cannot read " + path.string() + ": " + OIIO::geterror());
  std::vector<std::vector<float>> levels;
  for (size_t j = 0; j < sides.size(); ++j) {
    const std::string where = path.string() + " level " + std::to_string(j);
    if (!in->seek_subimage(0, static_cast<int>(j))) throw Error(ErrorCode::kInvalidArgument, where + " is missing");
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.width != sides[j] || spec.height != sides[j] || spec.nchannels != int(channels.size())) {
      throw Error(ErrorCode::kInvalidArgument, where + " does not match the manifest's size or channel count");
    }
    std::vector<int> order;
    for (const std::string& name : channels) {
      const int index = spec.channelindex(name);
      if (index < 0) throw Error(ErrorCode::kInvalidArgument, where + " has no channel " + name);
      order.push_back(index);
    }
    const size_t pixel_count = size_t(spec.width) * spec.height;
    std::vector<float> file(pixel_count * channels.size());
    if (!in->read_image(0, static_cast<int>(j), 0, spec.nchannels, OIIO::TypeDesc::FLOAT, file.data())) {
      throw Error(ErrorCode::kInvalidArgument, "cannot read " + where + ": " + in->geterror());
    }
    std::vector<float>& pixels = levels.emplace_back(file.size());
    for (size_t p = 0; p < pixel_count; ++p) {
      for (size_t c = 0; c < channels.size(); ++c) pixels[p * channels.size() + c] = file[p * channels.size() + order[c]];
    }
  }
  return levels;
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

// The manifest's levels: level 0 within the spatial-resolution caps, then either
// nothing more or every halving down to 1×1 (fitted mip levels need a power of
// two), and no more LUT texels than the radiance-sample cap allows.
template <typename Invalid>
void CheckLevelChain(const json& levels, uint64_t views, const Invalid& invalid) {
  if (!levels.is_array() || levels.empty()) throw invalid("levels is not a non-empty array");
  const auto first = levels[0].at("resolution").get<int64_t>();
  if (first < kMinSpatialResolution || first > kMaxSpatialResolution) {
    throw invalid("levels[0].resolution " + std::to_string(first) + " is not in [" +
                  std::to_string(kMinSpatialResolution) + ", " + std::to_string(kMaxSpatialResolution) + "]");
  }
  if (uint64_t(first) * uint64_t(first) * views > kMaxRadianceSamples / kMinDirections) {
    throw invalid(std::to_string(first) + "² texels × " + std::to_string(views) + " views exceed the sample caps");
  }
  const size_t chain = std::has_single_bit(uint64_t(first)) ? std::countr_zero(uint64_t(first)) + 1 : 1;
  if (levels.size() != 1 && levels.size() != chain) {
    throw invalid(std::to_string(levels.size()) + " levels for resolution " + std::to_string(first) +
                  ": either 1 or " + std::to_string(chain));
  }
  for (size_t j = 1; j < levels.size(); ++j) {
    const auto resolution = levels[j].at("resolution").get<int64_t>();
    if (resolution != first >> j) {
      throw invalid("levels[" + std::to_string(j) + "].resolution " + std::to_string(resolution) + " is not " +
                    std::to_string(first >> j));
    }
  }
}

// Verifies `name` in `directory` against the manifest's entry and its OpenEXR
// header against the level-0 side the manifest gives (core/image/exr_header.h)
// before OpenEXR reads it; returns its path.
std::filesystem::path VerifiedFile(const std::filesystem::path& directory, const json& files, const char* name,
                                   int side) {
  const std::filesystem::path path = directory / name;
  const std::string bytes = ReadFile(path);
  const json& entry = files.at(name);
  if (bytes.size() != entry.at("bytes").get<size_t>() || Sha256Hex(bytes) != entry.at("sha256").get<std::string>()) {
    throw Error(ErrorCode::kInvalidArgument,
                path.string() + " is corrupted: its size or SHA-256 differs from " + kManifestFile);
  }
  CheckExrHeader(bytes, side, side, path.string());
  return path;
}

}  // namespace

void WriteFabricAsset(const FittedFabric& fabric, const v1::PrecomputeSettings& settings,
                      const std::string& fabric_key, const std::filesystem::path& directory) {
  const v1::PrecomputeSettings resolved = WithDefaults(settings);
  const bool half = resolved.half_float();
  std::filesystem::create_directories(directory);
  const std::string parameters_sha = WriteLevelImage(ParameterImage(fabric), directory / kParametersFile, half);
  const std::string lut_sha = WriteLevelImage(LutImage(fabric), directory / kLutFile, half);

  json levels = json::array();
  for (const FittedLevel& level : fabric.levels) levels.push_back(StatsJson(level.stats));
  const json manifest = {
      {"asset_version", kAssetFormatVersion},
      {"fabric_key", fabric_key},
      {"settings", json::parse(SpecToJson(resolved, false))},
      {"lobes", fabric.lobes},
      {"lookup_table", fabric.lookup_table},
      {"sampling_height", fabric.sampling_height},
      {"half_float", half},
      {"resolution", fabric.levels.front().resolution},
      {"view_directions", fabric.view_directions.size()},
      {"fitted_levels", fabric.levels.size()},
      {"levels", levels},
      {"fit_seconds", fabric.seconds},
      {"files",
       {{kParametersFile,
         {{"bytes", std::filesystem::file_size(directory / kParametersFile)}, {"sha256", parameters_sha}}},
        {kLutFile, {{"bytes", std::filesystem::file_size(directory / kLutFile)}, {"sha256", lut_sha}}}}},
  };
  WriteFileAtomic(directory / kManifestFile, manifest.dump(2) + "\n");
}

FittedFabric ReadFabricAsset(const std::filesystem::path& directory) {
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
    CheckLevelChain(manifest.at("levels"), static_cast<uint64_t>(view_count), invalid);
    fabric.lobes = static_cast<uint32_t>(lobes);
    fabric.lookup_table = manifest.at("lookup_table");
    fabric.sampling_height = manifest.at("sampling_height");
    fabric.seconds = manifest.at("fit_seconds");
    fabric.view_directions = HemisphereGridDirections(static_cast<uint32_t>(view_count));
    const size_t views = fabric.view_directions.size();
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
      const size_t side = size_t{level.resolution} * k;
      for (size_t texel = 0; texel < level.brdfs.size(); ++texel) {
        const size_t x = texel % level.resolution, y = texel / level.resolution;
        for (size_t v = 0; v < views; ++v) {
          const float* pixel = &luts[j][((y * k + v / k) * side + x * k + v % k) * 4];
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
