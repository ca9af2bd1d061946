#include "core/methods/asset_pictures.h"

#include <algorithm>
#include <limits>
#include <utility>

#include <nlohmann/json.hpp>

#include "core/methods/fabric_method.h"
#include "core/util/error.h"
#include "core/util/file_io.h"

namespace loom {

Image TexelPicture(uint32_t resolution, const std::function<glm::vec3(size_t texel)>& value, PictureScale scale) {
  const int side = static_cast<int>(resolution);
  Image picture(side, side, 3);
  glm::vec3 low(std::numeric_limits<float>::max()), high(std::numeric_limits<float>::lowest());
  for (size_t texel = 0; texel < size_t{resolution} * resolution; ++texel) {
    const glm::vec3 v = value(texel);
    for (int c = 0; c < 3; ++c) {
      picture.pixels[texel * 3 + c] = v[c];
      low[c] = std::min(low[c], v[c]);
      high[c] = std::max(high[c], v[c]);
    }
  }
  const float largest = std::max({high.x, high.y, high.z});
  for (size_t i = 0; i < picture.pixels.size(); ++i) {
    float& p = picture.pixels[i];
    const int c = static_cast<int>(i % 3);
    if (scale == PictureScale::kMaximum) p = largest > 0.0f ? p / largest : 0.0f;
    if (scale == PictureScale::kRange) p = high[c] > low[c] ? (p - low[c]) / (high[c] - low[c]) : 0.5f;
    p = std::clamp(p, 0.0f, 1.0f);
  }
  return picture;
}

size_t TopDirection(const std::vector<glm::vec3>& directions) {
  const auto top = std::max_element(directions.begin(), directions.end(),
                                    [](const glm::vec3& a, const glm::vec3& b) { return a.z < b.z; });
  return static_cast<size_t>(top - directions.begin());
}

AssetPicture PerViewPicture(uint32_t level, std::string map, std::string caption, uint32_t resolution,
                            const std::vector<glm::vec3>& values, size_t views, size_t view) {
  return {level, std::move(map), std::move(caption),
          TexelPicture(
              resolution, [&](size_t texel) { return values[texel * views + view]; }, PictureScale::kMaximum)};
}

AssetPicture AmbientPicture(uint32_t level, uint32_t resolution, const std::vector<glm::vec3>& ambient, size_t views,
                            size_t view) {
  return PerViewPicture(level, "ambient", "ambient response seen from above, scaled to its maximum", resolution,
                        ambient, views, view);
}

AssetPicture CoveragePicture(uint32_t level, uint32_t resolution, const std::vector<float>& alpha, size_t views,
                             size_t view) {
  return {level, "alpha", "coverage alpha seen from above (black: a hole)",
          TexelPicture(
              resolution, [&](size_t texel) { return glm::vec3(alpha[texel * views + view]); },
              PictureScale::kReflectance)};
}

std::string AssetPictureFile(uint32_t level, std::string_view map) {
  return "picture_l" + std::to_string(level) + "_" + std::string(map) + ".png";
}

void WriteAssetPictures(const FabricAsset& asset, const std::filesystem::path& directory) {
  nlohmann::json list = nlohmann::json::array();
  for (const AssetPicture& picture : asset.Pictures()) {
    const bool plain = !picture.map.empty() && std::all_of(picture.map.begin(), picture.map.end(), [](char c) {
      return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
    });
    if (!plain) throw Error(ErrorCode::kInternal, "asset picture map name '" + picture.map + "' is not [a-z0-9_]+");
    const std::string file = AssetPictureFile(picture.level, picture.map);
    WriteImage(picture.image, directory / file);
    list.push_back({{"file", file}, {"level", picture.level}, {"map", picture.map}, {"caption", picture.caption}});
  }
  WriteFileAtomic(directory / kAssetPicturesFile, list.dump(1));
}

}  // namespace loom
