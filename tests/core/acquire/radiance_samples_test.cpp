#include "core/acquire/radiance_samples.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "core/acquire/hemisphere_directions.h"
#include "core/util/error.h"
#include "core/util/file_io.h"
#include "core/util/sha256.h"

namespace loom {
namespace {

// Samples with a distinct value in every slot.
RadianceSamples Filled() {
  RadianceSamples s(4, HemisphereGridDirections(9), HemisphereGridDirections(4));
  for (size_t i = 0; i < s.alpha.size(); ++i) s.alpha[i] = static_cast<float>(i % 5) / 4.0f;
  for (size_t i = 0; i < s.radiance.size(); ++i) s.radiance[i] = glm::vec3(i * 1e-3f, 1.0f / (i + 1), -0.0f);
  for (size_t t = 0; t < s.texel_count(); ++t) {
    s.normals[t] = glm::normalize(glm::vec3(0.1f * t, 0.2f, 1.0f));
    s.tangents[t] = glm::normalize(glm::vec3(1.0f, 0.0f, -0.1f * t));
    s.normal_lengths[t] = 1.0f / (t + 1);
  }
  for (size_t v = 0; v < s.view_count(); ++v) s.view_heights[v] = 0.3f - 0.01f * v;
  return s;
}

std::filesystem::path TempPath(const char* name) {
  const auto dir = std::filesystem::path(::testing::TempDir()) / "loom_radiance_samples_test";
  std::filesystem::create_directories(dir);
  return dir / name;
}

// The message of the Error(kInvalidArgument) that decoding `bytes` throws.
std::string DecodeError(const std::string& bytes) {
  try {
    DecodeRadianceSamples(bytes, "test.rsmp");
  } catch (const Error& error) {
    EXPECT_EQ(error.code(), ErrorCode::kInvalidArgument);
    return error.what();
  }
  ADD_FAILURE() << "decoding did not fail";
  return {};
}

TEST(RadianceSamples, LayoutIsTexelMajor) {
  const RadianceSamples s = Filled();
  EXPECT_EQ(s.AlphaIndex(2, 3), 2 * 9 + 3u);
  EXPECT_EQ(s.RadianceIndex(2, 3, 1), (2 * 9 + 3) * 4 + 1u);
  EXPECT_EQ(s.alpha.size(), 16 * 9u);
  EXPECT_EQ(s.radiance.size(), 16 * 9 * 4u);
}

TEST(RadianceSamples, FileRoundTripGivesBackIdenticalBits) {
  const RadianceSamples s = Filled();
  const auto path = TempPath("round_trip.rsmp");
  WriteRadianceSamples(s, path);
  const RadianceSamples back = ReadRadianceSamples(path);
  EXPECT_EQ(back, s);
  // Bit for bit, including the sign of −0.
  EXPECT_EQ(EncodeRadianceSamples(back), ReadFile(path));
  EXPECT_TRUE(std::signbit(back.radiance[0].b));
  // Documented size: header, floats, checksum.
  const size_t floats = 3 * (9 + 4) + 9 + 7 * 16 + 16 * 9 + 3 * 16 * 9 * 4;
  EXPECT_EQ(std::filesystem::file_size(path), 24 + 4 * floats + 64);
  EXPECT_EQ(ReadFile(path).substr(0, 8), "LOOMRSMP");
}

TEST(RadianceSamples, CorruptedTruncatedOrForeignFilesAreClearErrors) {
  const std::string good = EncodeRadianceSamples(Filled());

  std::string flipped = good;
  flipped[1000] ^= 0x01;
  EXPECT_NE(DecodeError(flipped).find("checksum mismatch"), std::string::npos);

  // A flipped header byte (the light count) is caught by the checksum too.
  std::string header = good;
  header[20] ^= 0x40;
  EXPECT_NE(DecodeError(header).find("checksum"), std::string::npos);

  EXPECT_NE(DecodeError(good.substr(0, good.size() - 100)).find("checksum"), std::string::npos);
  EXPECT_NE(DecodeError("P6 a picture").find("not a radiance samples file"), std::string::npos);
  EXPECT_NE(DecodeError("").find("not a radiance samples file"), std::string::npos);

  // Corrupt on disk: the error names the file.
  const auto path = TempPath("corrupt.rsmp");
  WriteFileAtomic(path, flipped);
  try {
    ReadRadianceSamples(path);
    FAIL();
  } catch (const Error& error) {
    EXPECT_EQ(error.code(), ErrorCode::kInvalidArgument);
    EXPECT_NE(std::string(error.what()).find(path.string()), std::string::npos);
  }
  try {
    ReadRadianceSamples(TempPath("missing.rsmp"));
    FAIL();
  } catch (const Error& error) {
    EXPECT_EQ(error.code(), ErrorCode::kNotFound);
  }
}

TEST(RadianceSamples, WellFormedFilesWithBadContentAreRejected) {
  RadianceSamples nan = Filled();
  nan.radiance[7].g = std::numeric_limits<float>::quiet_NaN();
  EXPECT_NE(DecodeError(EncodeRadianceSamples(nan)).find("non-finite"), std::string::npos);
  RadianceSamples infinite_height = Filled();
  infinite_height.view_heights[2] = std::numeric_limits<float>::infinity();
  EXPECT_NE(DecodeError(EncodeRadianceSamples(infinite_height)).find("non-finite"), std::string::npos);
  RadianceSamples short_heights = Filled();
  short_heights.view_heights.pop_back();
  EXPECT_THROW(EncodeRadianceSamples(short_heights), Error);

  RadianceSamples not_a_grid = Filled();
  not_a_grid.view_directions.resize(8);
  not_a_grid.view_heights.resize(8);
  not_a_grid.alpha.resize(not_a_grid.texel_count() * 8);
  not_a_grid.radiance.resize(not_a_grid.texel_count() * 8 * 4);
  EXPECT_NE(DecodeError(EncodeRadianceSamples(not_a_grid)).find("dimensions"), std::string::npos);

  RadianceSamples short_alpha = Filled();
  short_alpha.alpha.pop_back();
  EXPECT_THROW(EncodeRadianceSamples(short_alpha), Error);

  // Values the layout promises: every one of these would feed the fit nonsense.
  RadianceSamples bright = Filled();
  bright.alpha[3] = 1.5f;
  EXPECT_NE(DecodeError(EncodeRadianceSamples(bright)).find("an alpha or normal length is outside [0, 1]"),
            std::string::npos);
  RadianceSamples tilted = Filled();
  tilted.light_directions[2] = glm::normalize(tilted.light_directions[2] + glm::vec3(0.01f, 0, 0));
  EXPECT_NE(DecodeError(EncodeRadianceSamples(tilted)).find("not the hemisphere grid"), std::string::npos);
  RadianceSamples flat = Filled();
  flat.normals[1] = glm::vec3(0.0f);
  EXPECT_NE(DecodeError(EncodeRadianceSamples(flat)).find("not a unit vector"), std::string::npos);
  RadianceSamples negative = Filled();
  negative.radiance[5].r = -0.25f;
  EXPECT_NE(DecodeError(EncodeRadianceSamples(negative)).find("a radiance is negative"), std::string::npos);

  std::string future = EncodeRadianceSamples(Filled());
  future[8] = 4;  // version 4, checksum recomputed
  future = future.substr(0, future.size() - 64);
  future += loom::Sha256Hex(future);
  EXPECT_NE(DecodeError(future).find("version 4"), std::string::npos);
}

}  // namespace
}  // namespace loom
