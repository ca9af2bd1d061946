#pragma once
// A linear-radiance float image, top row first, channels interleaved. Files are
// read and written with OpenImageIO: EXR holds linear values (half float), PNG holds
// sRGB-encoded 8-bit values (converted on write and on read).

#include <filesystem>
#include <vector>

namespace loom {

struct Image {
  int width = 0;
  int height = 0;
  int channels = 0;
  std::vector<float> pixels;  // width * height * channels

  Image() = default;
  Image(int width, int height, int channels)
      : width(width), height(height), channels(channels),
        pixels(static_cast<size_t>(width) * height * channels, 0.0f) {}

  float& at(int x, int y, int c) { return pixels[(static_cast<size_t>(y) * width + x) * channels + c]; }
  float at(int x, int y, int c) const { return pixels[(static_cast<size_t>(y) * width + x) * channels + c]; }
};

// `image` with its rows in the opposite order: GL reads the bottom row first, images
// are stored top row first.
Image FlippedRows(const Image& image);

// Each `factor` × `factor` block of `image` averaged into one pixel; `image`'s sides are
// multiples of factor.
Image BoxDownsampled(const Image& image, int factor);

enum class ImageFileFormat { kPng, kExr };

// From the file extension (.png, .exr); throws Error(kInvalidArgument) otherwise.
ImageFileFormat FormatFromPath(const std::filesystem::path& path);

// Writes atomically (temp name, then rename). PNG: alpha is kept if present,
// colour clamped to [0, 1] and sRGB-encoded; EXR: half float, linear.
void WriteImage(const Image& image, const std::filesystem::path& path);

// Reads any format OpenImageIO knows; PNG/JPEG (sRGB) are linearised.
Image ReadImage(const std::filesystem::path& path);

float SrgbToLinear(float encoded);
float LinearToSrgb(float linear);

}  // namespace loom
