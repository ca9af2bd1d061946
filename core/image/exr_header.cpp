#include "core/image/exr_header.h"

#include <algorithm>

#include <cstdint>
#include <cstring>
#include <utility>

#include "core/util/error.h"

namespace loom {
namespace {

constexpr uint32_t kTiledFlag = 0x200;
constexpr uint32_t kLongNamesFlag = 0x400;
constexpr uint32_t kDeepFlag = 0x800;
constexpr uint32_t kMultipartFlag = 0x1000;
constexpr int kMaxAttributes = 1024;
constexpr uint32_t kMinTileSide = 16;
constexpr uint32_t kMaxTileSide = 65536;
// OpenImageIO reads a tiled file a whole tile at a time: a tile may be no larger than
// the image, or than this for a small image (Loom writes 32-pixel tiles at any size).
constexpr uint32_t kSmallImageTileSide = 64;

// Reads little-endian fields, each checked against the bytes left.
class Reader {
 public:
  Reader(std::string_view bytes, const std::string& source) : bytes_(bytes), source_(source) {}

  Error Invalid(const std::string& what) const {
    return Error(ErrorCode::kInvalidArgument, "OpenEXR header of " + source_ + ": " + what);
  }
  size_t left() const { return bytes_.size() - at_; }

  template <typename T>
  T Value() {
    if (left() < sizeof(T)) throw Invalid("ends inside a field");
    T value;
    std::memcpy(&value, bytes_.data() + at_, sizeof value);
    at_ += sizeof value;
    return value;
  }
  // A null-terminated name of at most `max` characters.
  std::string_view Name(size_t max) {
    const size_t end = bytes_.find('\0', at_);
    if (end == std::string_view::npos || end - at_ > max) throw Invalid("a name longer than " + std::to_string(max));
    const std::string_view name = bytes_.substr(at_, end - at_);
    at_ = end + 1;
    return name;
  }
  std::string_view Take(size_t n) {
    if (left() < n) throw Invalid("an attribute's size passes the end of the file");
    const std::string_view part = bytes_.substr(at_, n);
    at_ += n;
    return part;
  }

 private:
  std::string_view bytes_;
  const std::string& source_;
  size_t at_ = 0;
};

// The types OpenEXR reads a fixed number of bytes of, whatever the size field
// says: a mismatch would leave it reading the next attribute from the wrong place.
constexpr std::pair<std::string_view, size_t> kFixedSizes[] = {
    {"box2i", 16},    {"box2f", 16},   {"compression", 1}, {"lineOrder", 1}, {"envmap", 1},
    {"deepImageState", 1}, {"double", 8}, {"float", 4},    {"int", 4},       {"keycode", 28},
    {"rational", 8},  {"tiledesc", 9}, {"timecode", 8},    {"v2i", 8},       {"v2f", 8},
    {"v2d", 16},      {"v3i", 12},     {"v3f", 12},        {"v3d", 24},      {"m33f", 36},
    {"m33d", 72},     {"m44f", 64},    {"m44d", 128},      {"chromaticities", 32}};

template <typename T>
T At(std::string_view value, size_t offset) {
  T out;
  std::memcpy(&out, value.data() + offset, sizeof out);
  return out;
}

// Channels: a name, pixel type (int32), pLinear and 3 reserved bytes, x and y
// sampling (int32 each), and a null byte ending the list exactly at the end of the
// value (OpenEXR reads up to that null, not up to the size).
void CheckChannelList(std::string_view value, size_t max_name, const std::string& field, const Reader& in) {
  for (size_t at = 0;;) {
    const size_t end = value.find('\0', at);
    if (end == std::string_view::npos || end - at > max_name) throw in.Invalid(field + ": a bad channel name");
    if (end == at) {
      if (end + 1 != value.size()) throw in.Invalid(field + ": the list does not end at the attribute's end");
      return;
    }
    at = end + 1 + 16;
    if (at > value.size()) throw in.Invalid(field + ": a channel passes the attribute's end");
  }
}

}  // namespace

void CheckExrHeader(std::string_view bytes, int width, int height, const std::string& source) {
  Reader in(bytes, source);
  if (in.Value<uint32_t>() != 20000630) throw in.Invalid("not an OpenEXR file (magic number)");
  const uint32_t version = in.Value<uint32_t>();
  if ((version & 0xff) != 2 || (version & (kDeepFlag | kMultipartFlag)) != 0) {
    throw in.Invalid("version " + std::to_string(version) + " is not a single-part image of version 2");
  }
  const size_t max_name = (version & kLongNamesFlag) ? 255 : 31;
  bool data_window = false, tiles = false;
  uint32_t tile_width = 0, tile_height = 0;
  for (int count = 0;; ++count) {
    if (count == kMaxAttributes) throw in.Invalid("more than " + std::to_string(kMaxAttributes) + " attributes");
    const std::string_view name = in.Name(max_name);
    if (name.empty()) break;
    const std::string_view type = in.Name(max_name);
    const auto size = in.Value<int32_t>();
    if (size < 0) throw in.Invalid("attribute " + std::string(name) + " has a negative size");
    const std::string_view value = in.Take(static_cast<size_t>(size));
    const std::string field = "attribute " + std::string(name) + " (" + std::string(type) + ")";
    for (const auto& [fixed_type, fixed_size] : kFixedSizes) {
      if (type == fixed_type && value.size() != fixed_size) {
        throw in.Invalid(field + " is " + std::to_string(value.size()) + " bytes, not " + std::to_string(fixed_size));
      }
    }
    if (type == "chlist") CheckChannelList(value, max_name, field, in);
    if (type == "floatvector" && value.size() % 4 != 0) throw in.Invalid(field + " is not whole floats");
    if (name == "dataWindow") {
      if (type != "box2i") throw in.Invalid(field + " is not a box2i");
      const int32_t x0 = At<int32_t>(value, 0), y0 = At<int32_t>(value, 4);
      const int32_t x1 = At<int32_t>(value, 8), y1 = At<int32_t>(value, 12);
      if (x0 != 0 || y0 != 0 || int64_t{x1} + 1 != width || int64_t{y1} + 1 != height) {
        throw in.Invalid("the data window is not the expected " + std::to_string(width) + "×" +
                         std::to_string(height) + " pixels");
      }
      data_window = true;
    } else if (name == "tiles") {
      if (type != "tiledesc" || value.size() != 9) throw in.Invalid(field + " is not a 9-byte tiledesc");
      tile_width = At<uint32_t>(value, 0);
      tile_height = At<uint32_t>(value, 4);
      if (tile_width < kMinTileSide || tile_width > kMaxTileSide || tile_height < kMinTileSide ||
          tile_height > kMaxTileSide) {
        throw in.Invalid("tiles of " + std::to_string(tile_width) + "×" + std::to_string(tile_height) +
                         " pixels are outside [" + std::to_string(kMinTileSide) + ", " +
                         std::to_string(kMaxTileSide) + "]");
      }
      tiles = true;
    } else if (type == "preview") {
      // width, height, then 4 bytes a pixel: OpenEXR allocates from the first two.
      if (value.size() < 8 ||
          uint64_t{At<uint32_t>(value, 0)} * At<uint32_t>(value, 4) * 4 + 8 != value.size()) {
        throw in.Invalid(field + ": its dimensions disagree with its size");
      }
    } else if (type == "stringvector") {
      // Strings each with an int32 length: OpenEXR allocates every length it reads.
      for (size_t at = 0; at < value.size();) {
        if (value.size() - at < 4) throw in.Invalid(field + " ends inside a length");
        const auto length = At<int32_t>(value, at);
        at += 4;
        if (length < 0 || static_cast<size_t>(length) > value.size() - at) {
          throw in.Invalid(field + ": a string passes the attribute's end");
        }
        at += static_cast<size_t>(length);
      }
    }
  }
  if (!data_window) throw in.Invalid("no dataWindow");
  if (tiles != ((version & kTiledFlag) != 0)) throw in.Invalid("the tiles attribute disagrees with the version flags");
  const auto larger = [](uint32_t tile, int side) { return tile > std::max<uint32_t>(side, kSmallImageTileSide); };
  if (tiles && (larger(tile_width, width) || larger(tile_height, height))) {
    throw in.Invalid("tiles of " + std::to_string(tile_width) + "×" + std::to_string(tile_height) +
                     " pixels are larger than the " + std::to_string(width) + "×" + std::to_string(height) +
                     " image (and than " + std::to_string(kSmallImageTileSide) + ")");
  }
}

}  // namespace loom
