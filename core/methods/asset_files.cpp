#include "core/methods/asset_files.h"

#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cmath>

#include "core/acquire/hemisphere_directions.h"
#include "core/image/exr_header.h"
#include "core/spec/limits.h"
#include "core/spec/spec_json.h"
#include "core/util/file_io.h"
#include "core/util/sha256.h"

namespace loom {

namespace OIIO = OIIO_NAMESPACE;
using nlohmann::json;

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

void CheckLevelChain(const json& levels, uint64_t values_per_texel, uint64_t max_values,
                     const std::function<Error(const std::string&)>& invalid) {
  if (!levels.is_array() || levels.empty()) throw invalid("levels is not a non-empty array");
  const auto first = levels[0].at("resolution").get<int64_t>();
  if (first < kMinSpatialResolution || first > kMaxSpatialResolution) {
    throw invalid("levels[0].resolution " + std::to_string(first) + " is not in [" +
                  std::to_string(kMinSpatialResolution) + ", " + std::to_string(kMaxSpatialResolution) + "]");
  }
  if (uint64_t(first) * uint64_t(first) * values_per_texel > max_values) {
    throw invalid(std::to_string(first) + "² texels × " + std::to_string(values_per_texel) +
                  " values a texel exceed the cap of " + std::to_string(max_values));
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

std::filesystem::path VerifiedFile(const AssetSheet& directory, const json& files, const char* name,
                                   int side) {
  const std::filesystem::path path = directory / name;
  const std::string bytes = ReadFile(path);
  const json& entry = files.at(name);
  if (bytes.size() != entry.at("bytes").get<size_t>() || Sha256Hex(bytes) != entry.at("sha256").get<std::string>()) {
    throw Error(ErrorCode::kInvalidArgument,
                path.string() + " is corrupted: its size or SHA-256 differs from manifest.json");
  }
  CheckExrHeader(bytes, side, side, path.string());
  return path;
}

std::vector<float> AmbientAlphaAtlas(const std::vector<glm::vec3>& ambient, const std::vector<float>& alpha,
                                     uint32_t resolution, size_t views) {
  const uint32_t k = GridSide(views);
  const size_t texels = size_t{resolution} * resolution;
  std::vector<float> pixels(texels * views * 4);
  for (size_t texel = 0; texel < texels; ++texel) {
    for (size_t view = 0; view < views; ++view) {
      float* pixel = &pixels[DirectionAtlasPixel(texel, resolution, view, k) * 4];
      const glm::vec3 value = ambient[texel * views + view];
      std::copy_n(&value[0], 3, pixel);
      pixel[3] = alpha[texel * views + view];
    }
  }
  return pixels;
}

void ReadAmbientAlphaAtlas(const std::vector<float>& atlas, uint32_t resolution, size_t views,
                           std::vector<glm::vec3>& ambient, std::vector<float>& alpha,
                           const std::function<Error(const std::string&)>& invalid) {
  const uint32_t k = GridSide(views);
  const size_t texels = size_t{resolution} * resolution;
  ambient.resize(texels * views);
  alpha.resize(texels * views);
  for (size_t texel = 0; texel < texels; ++texel) {
    for (size_t view = 0; view < views; ++view) {
      const float* pixel = &atlas[DirectionAtlasPixel(texel, resolution, view, k) * 4];
      for (int c = 0; c < 4; ++c) {
        if (!(pixel[c] >= 0.0f && std::isfinite(pixel[c]))) throw invalid("a negative or non-finite ambient or alpha");
      }
      if (pixel[3] > 1.0f) throw invalid("an alpha above 1");
      ambient[texel * views + view] = glm::vec3(pixel[0], pixel[1], pixel[2]);
      alpha[texel * views + view] = pixel[3];
    }
  }
}

uint32_t ManifestDirectionCount(const json& manifest, const char* field,
                                const std::function<Error(const std::string&)>& invalid) {
  const auto count = manifest.at(field).get<int64_t>();
  if (count < kMinDirections || count > kMaxDirections) {
    throw invalid(std::string(field) + " " + std::to_string(count) + " is not in [" + std::to_string(kMinDirections) +
                  ", " + std::to_string(kMaxDirections) + "]");
  }
  const auto side = static_cast<int64_t>(std::lround(std::sqrt(static_cast<double>(count))));
  if (side * side != count) throw invalid(std::string(field) + " " + std::to_string(count) + " is not a k×k grid");
  return static_cast<uint32_t>(count);
}

json TableManifest(std::string_view method, uint32_t version, const std::string& fabric_key,
                   const v1::PrecomputeSettings& resolved, const TableAssetHeader& header, const json& levels) {
  return {{"method", method},
          {"asset_version", version},
          {"fabric_key", fabric_key},
          {"settings", json::parse(SpecToJson(resolved, false))},
          {"view_heights", header.view_heights},
          {"half_float", resolved.half_float()},
          {"resolution", header.resolution},
          {"view_directions", header.views},
          {"light_directions", header.lights},
          {"levels", levels},
          {"build_seconds", header.build_seconds}};
}

TableAssetHeader CheckTableManifest(const json& manifest, std::string_view method, uint32_t version,
                                    const std::function<Error(const std::string&)>& invalid) {
  if (manifest.at("method") != method) throw invalid("method is not " + std::string(method));
  if (manifest.at("asset_version").get<uint32_t>() != version) {
    throw invalid("asset version " + manifest.at("asset_version").dump() + ", this engine reads " +
                  std::to_string(version));
  }
  TableAssetHeader header;
  header.views = ManifestDirectionCount(manifest, "view_directions", invalid);
  header.lights = ManifestDirectionCount(manifest, "light_directions", invalid);
  header.view_heights = ManifestViewHeights(manifest, header.views, invalid);
  header.build_seconds = manifest.at("build_seconds");
  return header;
}

std::vector<float> ManifestViewHeights(const json& manifest, size_t views,
                                       const std::function<Error(const std::string&)>& invalid) {
  const json& heights = manifest.at("view_heights");
  if (!heights.is_array() || heights.size() != views) {
    throw invalid("view_heights is not an array of " + std::to_string(views) + " numbers, one per view");
  }
  std::vector<float> result;
  for (const json& height : heights) {
    const double value = height.get<double>();
    if (!std::isfinite(value) || std::abs(value) > 1e6) throw invalid("a view height is not a finite tile z");
    result.push_back(static_cast<float>(value));
  }
  return result;
}

json FileEntry(const std::filesystem::path& path, const std::string& sha256) {
  return {{"bytes", std::filesystem::file_size(path)}, {"sha256", sha256}};
}

}  // namespace loom
