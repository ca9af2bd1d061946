#pragma once
// Pictures of what a fabric method stores per texel, for people (the dashboard's
// fabric page): per level a few maps, one pixel per texel, each scaled to [0, 1] to
// be shown. A method says which maps it has (FabricAsset::Pictures); the worker writes
// them beside the asset with a list that names and describes each
// (WriteAssetPictures), so a page needs no knowledge of methods.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

#include "core/image/image.h"

namespace loom {

class FabricAsset;

struct AssetPicture {
  uint32_t level = 0;
  std::string map;      // [a-z0-9_]+, part of the file name
  std::string caption;  // what the picture shows
  Image image;          // linear RGB in [0, 1], one pixel per texel
};

// How a map's values become a picture's.
enum class PictureScale {
  kReflectance,  // as they are, clamped to [0, 1]
  kMaximum,      // divided by the largest value of any channel and texel (black stays black)
  kRange,        // each channel's smallest to largest value over the map onto [0, 1]
};

// The resolution² picture of value(texel), texel = y·resolution + x, scaled by `scale`.
Image TexelPicture(uint32_t resolution, const std::function<glm::vec3(size_t texel)>& value, PictureScale scale);

// The direction nearest the surface normal (the largest z): the view or light a
// picture of a per-direction table shows.
size_t TopDirection(const std::vector<glm::vec3>& directions);

// A map stored per (texel, view) at [texel·views + view], seen from view `view`,
// scaled to its maximum.
AssetPicture PerViewPicture(uint32_t level, std::string map, std::string caption, uint32_t resolution,
                            const std::vector<glm::vec3>& values, size_t views, size_t view);

// The pictures every table-based method has at a level: the ambient response and
// the coverage alpha, both seen from view `view` of `views`, per texel
// ([texel·views + view]).
AssetPicture AmbientPicture(uint32_t level, uint32_t resolution, const std::vector<glm::vec3>& ambient, size_t views,
                            size_t view);
AssetPicture CoveragePicture(uint32_t level, uint32_t resolution, const std::vector<float>& alpha, size_t views,
                             size_t view);

inline constexpr char kAssetPicturesFile[] = "pictures.json";

// "picture_l<level>_<map>.png".
std::string AssetPictureFile(uint32_t level, std::string_view map);

// Writes `asset`'s pictures as PNGs, then kAssetPicturesFile listing each as
// {"file", "level", "map", "caption"}, into `directory` (which exists). Throws
// Error(kInternal) for a map name outside [a-z0-9_]+.
void WriteAssetPictures(const FabricAsset& asset, const std::filesystem::path& directory);

}  // namespace loom
