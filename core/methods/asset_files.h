#pragma once
// The pieces every fabric method's asset directory is made of: images whose MIP
// levels are the method's levels (OpenEXR through OpenImageIO, written to a
// temporary name and renamed), and the manifest's checks on them before OpenEXR
// reads a byte (sizes, SHA-256, headers; the level chain within the caps).

#include <cstdint>
#include <filesystem>
#include <functional>
#include <glm/glm.hpp>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/methods/direction_grid.h"
#include "core/util/error.h"
#include "loom/v1/precompute.pb.h"

namespace loom {

// Where the files of one sheet of an asset lie: the asset's directory, and a prefix
// of their names ("" for the asset, kBackSheetPrefix for its back sheet,
// FabricAsset in core/methods/fabric_method.h): an asset stays one flat directory.
inline constexpr const char* kBackSheetPrefix = "back-";
struct AssetSheet {
  AssetSheet(std::filesystem::path directory, std::string prefix = {})  // NOLINT: a directory is the front sheet
      : directory(std::move(directory)), prefix(std::move(prefix)) {}
  std::filesystem::path operator/(std::string_view name) const { return directory / (prefix + std::string(name)); }
  std::filesystem::path directory;
  std::string prefix;
};

// One image with its MIP levels, pixel-interleaved floats, level j of side sides[j].
// Channels flagged in `keep_float` stay 32-bit in a half-float file.
struct LevelImage {
  std::vector<std::string> channel_names;
  std::vector<int> sides;
  std::vector<std::vector<float>> pixels;
  std::vector<bool> keep_float = std::vector<bool>(channel_names.size(), false);
};

// The pixel of texel `texel`'s stored direction `d` in a level's direction atlas
// (the view atlas of core/shaders/fabric_surface.glsl, and the light atlases of the
// methods with light tables): the texel's k×k block of directions at (x·k, y·k),
// direction (col, row) = (d % k, d / k) inside it, in a row-major image of side
// resolution·k.
inline size_t DirectionAtlasPixel(size_t texel, uint32_t resolution, size_t d, uint32_t k) {
  const size_t x = texel % resolution, y = texel / resolution, side = size_t{resolution} * k;
  return (y * k + d / k) * side + x * k + d % k;
}

// The view atlas of methods whose RGB is the ambient response: per (texel, view)
// ambient.rgb and alpha, RGBA floats (`views` a k×k grid); and back, Error
// (kInvalidArgument) through `invalid` for a value that is negative, non-finite or,
// for alpha, above 1.
std::vector<float> AmbientAlphaAtlas(const std::vector<glm::vec3>& ambient, const std::vector<float>& alpha,
                                     uint32_t resolution, size_t views);
void ReadAmbientAlphaAtlas(const std::vector<float>& atlas, uint32_t resolution, size_t views,
                           std::vector<glm::vec3>& ambient, std::vector<float>& alpha,
                           const std::function<Error(const std::string&)>& invalid);

// Those atlases of every level as one image (a method's views.exr): level ℓ of side
// res_ℓ·k. `Level` has resolution, ambient and alpha as TabulatedLevel has.
template <typename Level>
LevelImage AmbientAlphaImage(const std::vector<Level>& levels, size_t views) {
  LevelImage image{{"R", "G", "B", "A"}, {}, {}};
  for (const Level& level : levels) {
    image.pixels.push_back(AmbientAlphaAtlas(level.ambient, level.alpha, level.resolution, views));
    image.sides.push_back(static_cast<int>(level.resolution * GridSide(views)));
  }
  return image;
}

// Writes `image` to a temporary name beside `path`, then renames it; returns the
// file's SHA-256. Several levels become a tiled MIP-mapped OpenEXR, which must go
// down to 1×1: missing levels are point-sampled from the last given one (padding
// that no renderer reads).
std::string WriteLevelImage(const LevelImage& image, const std::filesystem::path& path, bool half);

// The first sides.size() levels of an image written by WriteLevelImage, channels in
// the order of `channels` (OpenEXR stores them sorted by name, so they are found by
// name). Error(kInvalidArgument) if a level's size or channels differ.
std::vector<std::vector<float>> ReadLevelImage(const std::filesystem::path& path, const std::vector<int>& sides,
                                               const std::vector<std::string>& channels);

// The manifest's "files" entry for a written file: its size and SHA-256.
nlohmann::json FileEntry(const std::filesystem::path& path, const std::string& sha256);

// Verifies `name` in `directory` against the manifest's "files" entry and its
// OpenEXR header against the level-0 side `side` (core/image/exr_header.h) before
// OpenEXR reads it; returns its path.
std::filesystem::path VerifiedFile(const AssetSheet& directory, const nlohmann::json& files,
                                   const char* name, int side);

// The manifest's direction count `field`: a k×k grid within the caps, else
// invalid(what) is thrown.
uint32_t ManifestDirectionCount(const nlohmann::json& manifest, const char* field,
                                const std::function<Error(const std::string&)>& invalid);

// The manifest's "levels": level 0 within the spatial-resolution caps, then either
// nothing more or every halving down to 1×1 (mip levels need a power of two), and
// at most `max_values` values of `values_per_texel` each at level 0. Throws
// invalid(what) otherwise.
void CheckLevelChain(const nlohmann::json& levels, uint64_t values_per_texel, uint64_t max_values,
                     const std::function<Error(const std::string&)>& invalid);

// What the manifests of the direction-table methods (tabulated, factored) share.
struct TableAssetHeader {
  uint32_t views = 0, lights = 0;  // direction counts, k×k grids
  uint32_t resolution = 0;         // level 0's texels a side
  std::vector<float> view_heights;  // RadianceSamples::view_heights
  double build_seconds = 0.0;
};

// The manifest's "view_heights" (RadianceSamples::view_heights): `views` finite
// numbers, else invalid(what) is thrown.
std::vector<float> ManifestViewHeights(const nlohmann::json& manifest, size_t views,
                                       const std::function<Error(const std::string&)>& invalid);

// Such a manifest: method, asset_version, fabric_key, settings (`resolved`, defaults
// applied), half_float, the header's fields and `levels`; the caller adds "files" and
// its own fields.
nlohmann::json TableManifest(std::string_view method, uint32_t version, const std::string& fabric_key,
                             const v1::PrecomputeSettings& resolved, const TableAssetHeader& header,
                             const nlohmann::json& levels);

// Checks such a manifest's method, version, direction counts and view heights
// (invalid(what) otherwise) and returns its header.
TableAssetHeader CheckTableManifest(const nlohmann::json& manifest, std::string_view method, uint32_t version,
                                    const std::function<Error(const std::string&)>& invalid);

}  // namespace loom
