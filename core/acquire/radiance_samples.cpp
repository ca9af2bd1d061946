#include "core/acquire/radiance_samples.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <numeric>
#include <utility>

#include "core/acquire/hemisphere_directions.h"
#include "core/spec/limits.h"
#include "core/util/error.h"
#include "core/util/vector_math.h"
#include "core/util/file_io.h"
#include "core/util/sha256.h"

namespace loom {

glm::vec3 TexelTangent(glm::vec3 n) {
  const glm::vec3 x(1, 0, 0);
  const glm::vec3 y(0, 1, 0);
  return SafeNormalize(x - n * glm::dot(n, x), SafeNormalize(y - n * glm::dot(n, y), x));
}
namespace {

// The file stores the in-memory representation; a big-endian host would need swaps.
static_assert(std::endian::native == std::endian::little, "the samples file is little-endian");
static_assert(sizeof(glm::vec3) == 3 * sizeof(float), "glm::vec3 must be three packed floats");

constexpr char kMagic[8] = {'L', 'O', 'O', 'M', 'R', 'S', 'M', 'P'};
constexpr uint32_t kVersion = 3;
constexpr size_t kHeaderBytes = sizeof kMagic + 4 * sizeof(uint32_t);
constexpr size_t kChecksumBytes = 64;  // SHA-256 as hex

template <typename T>
void Append(std::string& out, const std::vector<T>& values) {
  out.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
}

void AppendU32(std::string& out, uint32_t value) { out.append(reinterpret_cast<const char*>(&value), sizeof value); }

// Reads the fields in file order; the caller has checked the total size.
class Reader {
 public:
  explicit Reader(std::string_view bytes) : bytes_(bytes) {}
  uint32_t U32() {
    uint32_t value;
    std::memcpy(&value, Take(sizeof value), sizeof value);
    return value;
  }
  template <typename T>
  void Fill(std::vector<T>& values, size_t count) {
    values.resize(count);
    std::memcpy(values.data(), Take(count * sizeof(T)), count * sizeof(T));
  }

 private:
  const char* Take(size_t n) {
    const char* at = bytes_.data() + offset_;
    offset_ += n;
    return at;
  }
  std::string_view bytes_;
  size_t offset_ = 0;
};

template <typename T>
bool AllFinite(const std::vector<T>& values) {
  const auto* floats = reinterpret_cast<const float*>(values.data());
  return std::all_of(floats, floats + values.size() * sizeof(T) / sizeof(float),
                     [](float f) { return std::isfinite(f); });
}

}  // namespace

RadianceSamples::RadianceSamples(uint32_t resolution, std::vector<glm::vec3> views, std::vector<glm::vec3> lights)
    : resolution(resolution),
      view_directions(std::move(views)),
      light_directions(std::move(lights)),
      view_heights(view_count(), 0.0f),
      normals(texel_count(), glm::vec3(0, 0, 1)),
      tangents(texel_count(), glm::vec3(1, 0, 0)),
      normal_lengths(texel_count(), 1.0f),
      alpha(texel_count() * view_count(), 0.0f),
      radiance(texel_count() * view_count() * light_count(), glm::vec3(0.0f)) {}

double RadianceSamples::MeanAlpha() const {
  if (alpha.empty()) return 0.0;
  return std::accumulate(alpha.begin(), alpha.end(), 0.0) / static_cast<double>(alpha.size());
}

std::string EncodeRadianceSamples(const RadianceSamples& s) {
  // A file whose arrays disagree with its dimensions could never be read back.
  const size_t texels = s.texel_count();
  if (s.view_heights.size() != s.view_count() || s.normals.size() != texels || s.tangents.size() != texels || s.normal_lengths.size() != texels ||
      s.alpha.size() != texels * s.view_count() ||
      s.radiance.size() != texels * s.view_count() * s.light_count()) {
    throw Error(ErrorCode::kInvalidArgument, "radiance samples: array sizes do not match " +
                                                 std::to_string(s.resolution) + "² texels × " +
                                                 std::to_string(s.view_count()) + " views × " +
                                                 std::to_string(s.light_count()) + " lights");
  }
  std::string out(kMagic, sizeof kMagic);
  AppendU32(out, kVersion);
  AppendU32(out, s.resolution);
  AppendU32(out, static_cast<uint32_t>(s.view_count()));
  AppendU32(out, static_cast<uint32_t>(s.light_count()));
  Append(out, s.view_directions);
  Append(out, s.light_directions);
  Append(out, s.view_heights);
  Append(out, s.normals);
  Append(out, s.tangents);
  Append(out, s.normal_lengths);
  Append(out, s.alpha);
  Append(out, s.radiance);
  out += Sha256Hex(out);
  return out;
}

// The layout's promises about the values: the direction grids are the ones
// HemisphereGridDirections makes (fitting and the LUT rely on their order; the
// lights may be that grid mirrored below the cloth), alpha
// and normal lengths in [0, 1], unit normals and tangents, radiance >= 0.
template <typename Fail>
void CheckValues(const RadianceSamples& s, const Fail& fail) {
  // The grid, or with `mirrored` the grid below the cloth.
  const auto same_grid = [](const std::vector<glm::vec3>& given, bool mirrored) {
    std::vector<glm::vec3> grid = HemisphereGridDirections(static_cast<uint32_t>(given.size()));
    if (mirrored) grid = MirroredThroughTheSurface(std::move(grid));
    for (size_t i = 0; i < grid.size(); ++i) {
      if (glm::length(given[i] - grid[i]) > 1e-5f) return false;
    }
    return true;
  };
  if (!same_grid(s.view_directions, false) ||
      !(same_grid(s.light_directions, false) || same_grid(s.light_directions, true))) {
    throw fail("its view or light directions are not the hemisphere grid (core/acquire/hemisphere_directions.h)");
  }
  const auto unit = [](const glm::vec3& v) { return std::abs(glm::length(v) - 1.0f) < 1e-3f; };
  const auto fraction = [](float v) { return v >= 0.0f && v <= 1.0f; };
  if (!std::all_of(s.normals.begin(), s.normals.end(), unit) || !std::all_of(s.tangents.begin(), s.tangents.end(), unit)) {
    throw fail("a texel normal or tangent is not a unit vector");
  }
  if (!std::all_of(s.alpha.begin(), s.alpha.end(), fraction) ||
      !std::all_of(s.normal_lengths.begin(), s.normal_lengths.end(), fraction)) {
    throw fail("an alpha or normal length is outside [0, 1]");
  }
  if (!std::all_of(s.radiance.begin(), s.radiance.end(), [](const glm::vec3& r) { return glm::all(glm::greaterThanEqual(r, glm::vec3(0.0f))); })) {
    throw fail("a radiance is negative");
  }
}

RadianceSamples DecodeRadianceSamples(std::string_view bytes, const std::string& source) {
  auto fail = [&](const std::string& why) {
    return Error(ErrorCode::kInvalidArgument, "radiance samples " + source + ": " + why);
  };
  if (bytes.size() < kHeaderBytes + kChecksumBytes || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0) {
    throw fail("not a radiance samples file (no LOOMRSMP header)");
  }
  // The checksum first: dimensions from a damaged header must not drive allocation.
  const std::string_view body = bytes.substr(0, bytes.size() - kChecksumBytes);
  const std::string_view stored = bytes.substr(body.size());
  const std::string computed = Sha256Hex(body);
  if (stored != computed) {
    throw fail("checksum mismatch (stored " + std::string(stored.substr(0, 12)) + "…, computed " +
               computed.substr(0, 12) + "…): the file is corrupt or truncated");
  }

  Reader in(body.substr(sizeof kMagic));
  const uint32_t version = in.U32();
  if (version != kVersion) {
    throw fail("version " + std::to_string(version) + "; this build reads version " + std::to_string(kVersion));
  }
  RadianceSamples s;
  s.resolution = in.U32();
  const uint32_t views = in.U32();
  const uint32_t lights = in.U32();
  const auto in_range = [](uint32_t count, uint32_t min, uint32_t max) { return count >= min && count <= max; };
  const auto grid = [&](uint32_t count) {
    const auto side = static_cast<uint32_t>(std::lround(std::sqrt(static_cast<double>(count))));
    return in_range(count, kMinDirections, kMaxDirections) && side * side == count;
  };
  const size_t texels = s.texel_count();
  if (!in_range(s.resolution, kMinSpatialResolution, kMaxSpatialResolution) || !grid(views) || !grid(lights) ||
      texels * views * lights > kMaxRadianceSamples) {
    throw fail("dimensions " + std::to_string(s.resolution) + "² texels × " + std::to_string(views) + " views × " +
               std::to_string(lights) + " lights are not k×k direction grids within the caps of core/spec/limits.h");
  }
  const size_t floats = 3 * (views + lights) + views + 7 * texels + texels * views + 3 * texels * views * lights;
  if (body.size() != kHeaderBytes + floats * sizeof(float)) {
    throw fail("size " + std::to_string(bytes.size()) + " bytes does not match its dimensions");
  }
  in.Fill(s.view_directions, views);
  in.Fill(s.light_directions, lights);
  in.Fill(s.view_heights, views);
  in.Fill(s.normals, texels);
  in.Fill(s.tangents, texels);
  in.Fill(s.normal_lengths, texels);
  in.Fill(s.alpha, texels * views);
  in.Fill(s.radiance, texels * views * lights);
  if (!(AllFinite(s.view_directions) && AllFinite(s.light_directions) && AllFinite(s.view_heights) && AllFinite(s.normals) &&
        AllFinite(s.tangents) && AllFinite(s.normal_lengths) && AllFinite(s.alpha) && AllFinite(s.radiance))) {
    throw fail("contains a non-finite number");
  }
  CheckValues(s, fail);
  return s;
}

void WriteRadianceSamples(const RadianceSamples& samples, const std::filesystem::path& path) {
  WriteFileAtomic(path, EncodeRadianceSamples(samples));
}

RadianceSamples ReadRadianceSamples(const std::filesystem::path& path) {
  return DecodeRadianceSamples(ReadFile(path), path.string());
}

}  // namespace loom
