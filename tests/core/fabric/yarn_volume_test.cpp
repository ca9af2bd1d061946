// The yarn volume (core/fabric/yarn_volume.h): sections swept along centre lines, turned
// by the ply twist, seamless across periodic copies; and its march
// (core/acquire/volume_radiance.h) against quadrature of the same density.

#include "core/fabric/yarn_volume.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/acquire/fibre_walk.h"
#include "core/acquire/volume_radiance.h"
#include "core/fabric/fabric_tile.h"
#include "core/spec/defaults.h"
#include "core/spec/spec_json.h"

namespace loom {
namespace {

constexpr float kRadius = 0.1f;
constexpr float kPi = std::numbers::pi_v<float>;

v1::FabricSpec OneYarn(uint32_t plies, float fuzz, float twist_degrees) {
  v1::FabricSpec fabric;
  fabric.mutable_knit();
  v1::YarnSpec* yarn = fabric.add_yarns();
  yarn->set_radius(kRadius);
  yarn->set_plies(plies);
  yarn->set_fuzz(fuzz);
  yarn->set_twist_degrees(twist_degrees);
  return fabric;
}

// A straight yarn along x through (·, 0.5, 0), one period per tile, in a tile whose
// model and tile units agree. Its section's frame: N = +z, B = −y.
TileYarns StraightYarn() {
  PeriodicYarn yarn;
  constexpr int kSegments = 40;
  for (int i = 0; i <= kSegments; ++i) {
    yarn.points.push_back({static_cast<float>(i) / kSegments, 0.5f, 0.0f});
    yarn.tangents.push_back({1, 0, 0});
    yarn.section.push_back(glm::vec2(kRadius));
  }
  yarn.segment_yarn.assign(kSegments, 0);
  yarn.period = {1, 0, 0};
  return TileYarns{{yarn}, glm::vec3(1.0f)};
}

// ∫ρ over the unit section (yarn radii), by a fine grid.
double SectionIntegral(const YarnSection& section) {
  constexpr int kCells = 800;
  const float extent = section.extent(), cell = 2 * extent / kCells;
  double sum = 0.0;
  for (int y = 0; y < kCells; ++y) {
    for (int x = 0; x < kCells; ++x) {
      sum += FibreDensity(section, {-extent + (x + 0.5f) * cell, -extent + (y + 0.5f) * cell});
    }
  }
  return sum * cell * cell;
}

TEST(YarnVolume, ACrossSectionHoldsTheSectionsFibres) {
  const v1::FabricSpec fabric = OneYarn(3, 0.3f, 30.0f);
  const YarnVolume volume(StraightYarn(), fabric);
  const YarnSection section = MakeYarnSection(fabric.yarns(0));
  // ∫σ dA over the plane x = 0.3 = γ/R · R² ∫ρ dA (unit section).
  const double expected = kYarnOpticalDensity * kRadius * SectionIntegral(section);
  constexpr int kCells = 400;
  const float half = section.extent() * kRadius * 1.01f, cell = 2 * half / kCells;
  double sum = 0.0;
  for (int j = 0; j < kCells; ++j) {
    for (int i = 0; i < kCells; ++i) {
      sum += volume.Sample({0.3f, 0.5f - half + (i + 0.5f) * cell, -half + (j + 0.5f) * cell}).extinction;
    }
  }
  EXPECT_NEAR(sum * cell * cell / expected, 1.0, 5e-3);
  // Nothing beyond the flyaways' reach.
  EXPECT_EQ(volume.Sample({0.3f, 0.5f, half * 1.05f}).extinction, 0.0f);
}

// The mean |density before − density after| over the section across `joint` (direction
// `along`), relative to the mean density there.
float JointMismatch(const YarnVolume& volume, glm::vec3 joint, glm::vec3 along, float radius) {
  const glm::vec3 side = glm::normalize(glm::cross(along, glm::vec3(0, 0, 1))), up = glm::cross(side, along);
  double difference = 0.0, total = 0.0;
  for (float r = 0.05f; r < 1.0f; r += 0.1f) {
    for (float a = 0.0f; a < 2 * kPi; a += 0.05f) {
      const glm::vec3 q = r * radius * (std::cos(a) * side + std::sin(a) * up);
      const float before = volume.Sample(joint + q - 1e-4f * along).extinction;
      const float after = volume.Sample(joint + q + 1e-4f * along).extinction;
      difference += std::abs(before - after);
      total += before + after;
    }
  }
  return static_cast<float>(2.0 * difference / std::max(total, 1e-30));
}

TEST(YarnVolume, PliesTurnAtTheTwistRateAndJoinTheirPeriodicCopySeamlessly) {
  const v1::FabricSpec fabric = OneYarn(3, 0.0f, 30.0f);
  const YarnVolume volume(StraightYarn(), fabric);
  const YarnSection section = MakeYarnSection(fabric.yarns(0));
  // The twist rate tan ψ / (ply offset · R), rounded to whole turns per period (a
  // straight line has no holonomy).
  const float rate = std::tan(30.0f * kPi / 180.0f) / (section.ply_offset * kRadius);
  const float turn = 2 * kPi * std::round(rate / (2 * kPi));
  ASSERT_GT(turn, 0.0f);
  for (float x = 0.0f; x < 1.0f; x += 0.0625f) {
    const float angle = turn * x;
    // N = +z, B = −y: a ply centre at angle a is at z = o cos a, y = 0.5 − o sin a.
    const float o = section.ply_offset * kRadius;
    const glm::vec3 centre(x, 0.5f - o * std::sin(angle), o * std::cos(angle));
    EXPECT_NEAR(volume.Sample(centre).extinction, kYarnOpticalDensity * (1 - kFibreDensityEpsilon) / kRadius, 0.05f)
        << "x " << x;
    const glm::vec3 between(x, 0.5f - o * std::sin(angle + kPi / 3), o * std::cos(angle + kPi / 3));
    EXPECT_LT(volume.Sample(between).extinction, 0.5f * volume.Sample(centre).extinction) << "x " << x;
  }
  // Across the period's end: the same density either side (a ply's edge, where the
  // density steps from ε to 0, may fall between two points 2·10⁻⁴ apart: compare means).
  EXPECT_LT(JointMismatch(volume, {1.0f, 0.5f, 0.0f}, {1, 0, 0}, kRadius), 0.01f);
}

// A real knit: each course's yarn ends where its next copy starts, with a transported
// frame that need not match; the section still joins seamlessly there.
TEST(YarnVolume, AKnitsYarnIsSeamlessWhereItsPeriodicCopiesJoin) {
  const FabricTile tile = BuildFabricTile(
      ParseSpecJson<v1::FabricSpec>(R"({"knit": {"wales": 2, "courses": 2}, "yarns": [{"plies": 2, "twist_degrees": 25}]})",
                                    "fabric"));
  ASSERT_NE(tile.volume, nullptr);
  const YarnCurve& curve = tile.curves[0];
  const glm::vec3 along = glm::normalize(curve.points[1] - curve.points[0]);
  EXPECT_LT(JointMismatch(*tile.volume, curve.points.front(), along, curve.radius), 0.01f);
  // Elsewhere along the yarn, the same measure.
  const size_t middle = curve.points.size() / 3;
  EXPECT_LT(JointMismatch(*tile.volume, curve.points[middle],
                          glm::normalize(curve.points[middle + 1] - curve.points[middle]), curve.radius),
            0.01f);
}

TEST(YarnVolume, OnePlysFibresLeanByTheTwistAngleAtTheYarnsSurface) {
  const YarnVolume volume(StraightYarn(), OneYarn(1, 0.2f, 20.0f));
  const VolumeSample sample = volume.Sample({0.3f, 0.5f, 0.999f * kRadius});
  EXPECT_NEAR(glm::dot(sample.fibre, glm::vec3(1, 0, 0)), std::cos(20.0f * kPi / 180.0f), 2e-3f);
  EXPECT_NEAR(glm::length(sample.fibre), 1.0f, 1e-5f);
  // At the centre line the fibres run along it.
  EXPECT_NEAR(volume.Sample({0.3f, 0.5f, 0.0f}).fibre.x, 1.0f, 1e-5f);
}

// Light straight through the yarn at a distance d from its centre keeps e^{−γ/R ∫ρ}
// (eq. 5), the march against fine quadrature of the section's density.
TEST(YarnVolume, LightThroughTheYarnKeepsWhatItsDensityIntegralSays) {
  const v1::FabricSpec fabric = OneYarn(2, 0.5f, 25.0f);
  const YarnVolume volume(StraightYarn(), fabric);
  const YarnSection section = MakeYarnSection(fabric.yarns(0));
  for (float d : {0.05f, 0.4f, 0.8f, 0.97f, 1.2f}) {
    const float x = 0.35f;
    // The section's turn at x is whatever the volume chose; quadrature of the volume's
    // own density along the same line checks the march, and at d beyond the plies (the
    // flyaways, rotation-invariant) the section's formula checks the volume.
    double optical = 0.0, formula = 0.0;
    constexpr int kSteps = 20000;
    const float half = section.extent() * kRadius, dz = 2 * half / kSteps;
    for (int k = 0; k < kSteps; ++k) {
      const float z = -half + (k + 0.5f) * dz;
      optical += volume.Sample({x, 0.5f + d * kRadius, z}).extinction * dz;
      formula += kYarnOpticalDensity / kRadius * FibreDensity(section, glm::vec2(d, z / kRadius)) * dz;
    }
    const glm::vec3 top(x, 0.5f + d * kRadius, volume.z_max() + 0.01f);
    const float marched = VolumeTransmittance(volume, top, {0, 0, -1}, 0.5f);
    EXPECT_NEAR(marched, std::exp(-optical), 0.01f + 0.02f * std::exp(-optical)) << "d " << d;
    if (d > 1.0f) {
      EXPECT_NEAR(optical, formula, 1e-3 * formula + 1e-6) << "d " << d;
    }
  }
}

TEST(YarnVolume, AMarchsWeightsAddUpToItsOpacity) {
  const YarnVolume volume(StraightYarn(), OneYarn(2, 0.3f, 25.0f));
  const glm::vec3 direction = glm::normalize(glm::vec3(0.3f, 0.2f, -1.0f));
  for (float y : {0.42f, 0.47f, 0.5f, 0.55f}) {
    float weights = 0.0f;
    const float left = MarchVolume(volume, {0.3f, y, volume.z_max()}, direction, 0.25f,
                                   [&](const VolumeStep& step) { weights += step.weight; });
    EXPECT_NEAR(weights + left, 1.0f, left == 0.0f ? kMinVolumeTransmittance : 1e-5f) << y;
  }
}

// Acquisition's transmittance grid against marching each point, over a knit's slab,
// for light from above and from behind, steep and grazing: point by point, and weighted by
// the fibre density, where the light scatters. Across a yarn's edge, interpolating T alone
// is too bright by up to 1.4× at the grazing light (7–10% at the others), interpolating τ
// alone too dark by up to 0.7×.
TEST(LightTransmittance, FollowsTheMarchedTransmittanceOfAKnit) {
  const FabricTile tile = BuildFabricTile(ParseSpecJson<v1::FabricSpec>(
      R"({"knit": {"wales": 2, "courses": 2}, "yarns": [{"plies": 2, "twist_degrees": 25, "fuzz": 0.3}]})", "fabric"));
  const YarnVolume& volume = *tile.volume;
  for (const glm::vec3 light : {glm::vec3(0, 0, 1), glm::normalize(glm::vec3(0.5f, -0.3f, 0.6f)),
                                glm::normalize(glm::vec3(-0.9f, 0.2f, 0.15f)), glm::normalize(glm::vec3(0.2f, 0.4f, -0.7f))}) {
    LightTransmittance grid(volume, light);
    grid.MarchColumns(volume, 0, grid.column_count());
    double difference = 0.0, mean = 0.0, scattered_grid = 0.0, scattered_marched = 0.0;
    constexpr int kPoints = 20000;
    uint32_t state = 12345;
    auto uniform = [&] { return static_cast<float>((state = state * 1664525u + 1013904223u) >> 8) * 0x1p-24f; };
    for (int i = 0; i < kPoints; ++i) {
      const glm::vec3 p(uniform(), uniform(), volume.z_min() + uniform() * (volume.z_max() - volume.z_min()));
      const float marched = VolumeTransmittance(volume, p, light, 0.5f);
      difference += std::abs(grid(p) - marched);
      mean += marched;
      const float density = volume.Sample(p).extinction;
      scattered_grid += density * grid(p);
      scattered_marched += density * marched;
    }
    EXPECT_LT(difference / kPoints, 0.02) << light.x << " " << light.y << " " << light.z << ", mean T " << mean / kPoints;
    EXPECT_NEAR(scattered_grid / scattered_marched, 1.0, 0.06) << light.x << " " << light.y << " " << light.z;
    EXPECT_GT(mean / kPoints, 0.05);
  }
}

TEST(FibreScattering, ScattersTheDiffusePartWithThePhysicalAlbedoAndFollowsTheFibre) {
  YarnMaterial material;
  material.diffuse_albedo = glm::vec3(0.6f, 0.3f, 0.1f);
  material.specular_albedo = glm::vec3(0.0f);
  const glm::vec3 fibre(1, 0, 0), up(0, 0, 1);
  // Across the fibre: α / π² (fibre_walk.h), α the physical albedo.
  const glm::vec3 f = FibreScattering(material, fibre, up, up);
  const glm::vec3 alpha = FibreAlbedo(material.diffuse_albedo);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(f[c], alpha[c] / (kPi * kPi), 1e-6f);
  // Light along the fibre: its cross-section vanishes.
  EXPECT_NEAR(FibreScattering(material, fibre, fibre, up).r, 0.0f, 1e-6f);
  const glm::vec3 tilted = glm::normalize(glm::vec3(1, 0, 1));
  EXPECT_NEAR(FibreScattering(material, fibre, tilted, up).r, f.r * std::sqrt(0.5f), 1e-6f);
}

}  // namespace
}  // namespace loom
