#include "core/image/image.h"

#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include "core/util/error.h"

namespace loom {

namespace OIIO = OIIO_NAMESPACE;

float SrgbToLinear(float encoded) {
  return encoded <= 0.04045f ? encoded / 12.92f : std::pow((encoded + 0.055f) / 1.055f, 2.4f);
}

float LinearToSrgb(float linear) {
  linear = std::clamp(linear, 0.0f, 1.0f);
  return linear <= 0.0031308f ? 12.92f * linear : 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}

ImageFileFormat FormatFromPath(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(), ::tolower);
  if (extension == ".png") return ImageFileFormat::kPng;
  if (extension == ".exr") return ImageFileFormat::kExr;
  throw Error(ErrorCode::kInvalidArgument,
              "output image " + path.string() + ": unsupported extension '" + extension +
                  "' (allowed: .png for sRGB, .exr for linear)");
}

void WriteImage(const Image& image, const std::filesystem::path& path) {
  const ImageFileFormat format = FormatFromPath(path);
  if (image.width <= 0 || image.height <= 0 || image.channels <= 0) {
    throw Error(ErrorCode::kInvalidArgument, "cannot write an empty image to " + path.string());
  }
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
  // The temp name keeps the extension: OpenImageIO picks the writer by it.
  std::filesystem::path temp = path;
  temp.replace_filename(".tmp-" + std::to_string(::getpid()) + "-" + path.filename().string());

  auto out = OIIO::ImageOutput::create(temp.string());
  if (!out) throw Error(ErrorCode::kInternal, "OpenImageIO cannot create a writer for " + path.string());
  const bool png = format == ImageFileFormat::kPng;
  OIIO::ImageSpec spec(image.width, image.height, image.channels,
                       png ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::HALF);
  spec.attribute("oiio:ColorSpace", png ? "sRGB" : "linear");
  if (image.channels == 4) spec.alpha_channel = 3;

  bool ok = out->open(temp.string(), spec);
  if (ok && png) {
    std::vector<uint8_t> encoded(image.pixels.size());
    for (size_t i = 0; i < encoded.size(); ++i) {
      const bool alpha = image.channels == 4 && i % 4 == 3;
      const float value = alpha ? std::clamp(image.pixels[i], 0.0f, 1.0f) : LinearToSrgb(image.pixels[i]);
      encoded[i] = static_cast<uint8_t>(std::lround(value * 255.0f));
    }
    ok = out->write_image(OIIO::TypeDesc::UINT8, encoded.data());
  } else if (ok) {
    // Half floats end at 65504: a brighter finite value would be stored as Inf and
    // read back as a non-finite pixel. NaN stays NaN (it marks a bug to find).
    constexpr float kHalfMax = 65504.0f;
    std::vector<float> pixels = image.pixels;
    for (float& value : pixels) {
      if (std::isfinite(value)) value = std::clamp(value, -kHalfMax, kHalfMax);
    }
    ok = out->write_image(OIIO::TypeDesc::FLOAT, pixels.data());
  }
  ok = ok && out->close();
  if (!ok) {
    std::error_code ignored;
    std::filesystem::remove(temp, ignored);
    throw Error(ErrorCode::kUnavailable, "cannot write " + path.string() + ": " + out->geterror());
  }
  std::filesystem::rename(temp, path);
}

Image ReadImage(const std::filesystem::path& path) {
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) {
    throw Error(ErrorCode::kNotFound, "cannot read image " + path.string() + ": " + OIIO::geterror());
  }
  const OIIO::ImageSpec& spec = in->spec();
  Image image(spec.width, spec.height, spec.nchannels);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.pixels.data())) {
    throw Error(ErrorCode::kInvalidArgument, "cannot decode image " + path.string() + ": " + in->geterror());
  }
  const std::string colour_space = spec.get_string_attribute("oiio:ColorSpace", "linear");
  if (colour_space == "sRGB") {
    for (size_t i = 0; i < image.pixels.size(); ++i) {
      if (spec.alpha_channel >= 0 && static_cast<int>(i % spec.nchannels) == spec.alpha_channel) continue;
      image.pixels[i] = SrgbToLinear(image.pixels[i]);
    }
  }
  return image;
}

Image FlippedRows(const Image& image) {
  Image flipped(image.width, image.height, image.channels);
  const size_t row = static_cast<size_t>(image.width) * image.channels;
  for (int y = 0; y < image.height; ++y) {
    std::copy_n(image.pixels.begin() + static_cast<ptrdiff_t>(row * (image.height - 1 - y)), row,
                flipped.pixels.begin() + static_cast<ptrdiff_t>(row * y));
  }
  return flipped;
}

Image BoxDownsampled(const Image& image, int factor) {
  Image small(image.width / factor, image.height / factor, image.channels);
  const float weight = 1.0f / static_cast<float>(factor * factor);
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      for (int c = 0; c < image.channels; ++c) small.at(x / factor, y / factor, c) += weight * image.at(x, y, c);
    }
  }
  return small;
}

}  // namespace loom
