#include "core/image/exr_header.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>

#include "core/image/image.h"
#include "core/methods/asset_files.h"
#include "core/util/error.h"
#include "core/util/file_io.h"

namespace loom {
namespace {

// A real OpenEXR file as OpenImageIO writes it: 8×4 pixels, RGBA.
std::string SmallExr() {
  const auto path = std::filesystem::temp_directory_path() / "loom_exr_header_test.exr";
  Image image(8, 4, 4);
  WriteImage(image, path);
  std::string bytes = ReadFile(path);
  std::filesystem::remove(path);
  return bytes;
}

std::string ErrorOf(const std::string& bytes, int width = 8, int height = 4) {
  try {
    CheckExrHeader(bytes, width, height, "test.exr");
  } catch (const Error& error) {
    EXPECT_EQ(error.code(), ErrorCode::kInvalidArgument);
    return error.what();
  }
  return "";
}

// The byte offset of attribute `name`'s int32 size field.
size_t SizeFieldOf(const std::string& bytes, const std::string& name) {
  const size_t at = bytes.find(name + '\0');
  EXPECT_NE(at, std::string::npos) << name;
  return bytes.find('\0', at + name.size() + 1) + 1;
}

void SetInt(std::string& bytes, size_t at, int32_t value) { std::memcpy(&bytes[at], &value, sizeof value); }

// A tiled MIP-mapped file as a fabric asset writes it: 8×8 pixels, 32-pixel tiles.
std::string SmallTiledExr() {
  const auto path = std::filesystem::temp_directory_path() / "loom_exr_header_tiled_test.exr";
  LevelImage image{{"R", "G", "B"}, {8, 4}, {std::vector<float>(8 * 8 * 3, 0.5f), std::vector<float>(4 * 4 * 3, 0.5f)}};
  WriteLevelImage(image, path, /*half=*/true);
  std::string bytes = ReadFile(path);
  std::filesystem::remove(path);
  return bytes;
}

TEST(ExrHeader, AFileOpenImageIoWroteIsAccepted) {
  EXPECT_EQ(ErrorOf(SmallExr()), "");
}

// What fuzz/asset_fuzzer found next: a tile far larger than the image, which
// OpenImageIO allocates whole (805 MB for a 16384×4096 RGB float tile).
TEST(ExrHeader, TilesLargerThanTheImageAreRefused) {
  std::string bytes = SmallTiledExr();
  EXPECT_EQ(ErrorOf(bytes, 8, 8), "");  // 32-pixel tiles over 8 pixels: within the small-image allowance
  const size_t value = SizeFieldOf(bytes, "tiles") + 4;
  SetInt(bytes, value, 16384);
  SetInt(bytes, value + 4, 4096);
  EXPECT_NE(ErrorOf(bytes, 8, 8).find("tiles of 16384×4096 pixels are larger than the 8×8 image"), std::string::npos)
      << ErrorOf(bytes, 8, 8);
}

TEST(ExrHeader, ADataWindowOtherThanTheExpectedOneIsRefused) {
  EXPECT_NE(ErrorOf(SmallExr(), 16, 16).find("the data window is not the expected 16×16 pixels"), std::string::npos);
}

// What fuzz/asset_fuzzer found: a size field far past the file's end, which
// OpenEXR 3.1 allocates before reading.
TEST(ExrHeader, AnAttributeSizePastTheEndOfTheFileIsRefused) {
  std::string bytes = SmallExr();
  SetInt(bytes, SizeFieldOf(bytes, "compression"), 1'919'120'129);
  EXPECT_NE(ErrorOf(bytes).find("passes the end of the file"), std::string::npos) << ErrorOf(bytes);
}

// A fixed-size attribute with another size would make OpenEXR read the next
// attribute from the wrong place (and allocate whatever it finds there).
TEST(ExrHeader, FixedSizeAttributesMustHaveTheirSize) {
  std::string bytes = SmallExr();
  SetInt(bytes, SizeFieldOf(bytes, "pixelAspectRatio"), 3);
  EXPECT_NE(ErrorOf(bytes).find("is 3 bytes, not 4"), std::string::npos) << ErrorOf(bytes);
}

TEST(ExrHeader, AChannelListMustEndAtItsAttributesEnd) {
  std::string bytes = SmallExr();
  const size_t size_at = SizeFieldOf(bytes, "channels");
  int32_t size = 0;
  std::memcpy(&size, &bytes[size_at], sizeof size);
  bytes[size_at + 4 + static_cast<size_t>(size) - 1] = 'x';  // the terminating null
  EXPECT_NE(ErrorOf(bytes).find("channels"), std::string::npos) << ErrorOf(bytes);
}

TEST(ExrHeader, OtherFilesAndMultiPartFilesAreRefused) {
  EXPECT_NE(ErrorOf("P6 8 4 255").find("not an OpenEXR file"), std::string::npos);
  std::string bytes = SmallExr();
  bytes[5] = static_cast<char>(bytes[5] | 0x10);  // the multi-part flag (0x1000)
  EXPECT_NE(ErrorOf(bytes).find("not a single-part image"), std::string::npos);
  EXPECT_NE(ErrorOf(bytes.substr(0, 40)).find("test.exr"), std::string::npos);
}

}  // namespace
}  // namespace loom
