// A yarn's lumislice table (core/methods/lumislice/lumislice_table.h): light through the
// section as eq. 5 says, the light scattered between fibres as walks through the twisted
// yarn give it, the levels of detail as eq. 11 derives them.

#include "core/methods/lumislice/lumislice_table.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/acquire/fibre_walk.h"
#include "core/fabric/yarn_volume.h"
#include "core/util/error.h"

namespace loom {
namespace {

YarnSection SectionOf(uint32_t plies, float fuzz, float twist_degrees) {
  v1::YarnSpec yarn;
  yarn.set_plies(plies);
  yarn.set_fuzz(fuzz);
  yarn.set_twist_degrees(twist_degrees);
  return MakeYarnSection(yarn);
}

// Without fibre walks (I_msp 0) unless a test asks for them.
LumisliceSettings Settings(int resolution, int walks = 0) {
  LumisliceSettings settings;
  settings.resolution = resolution;
  settings.walks = walks;
  return settings;
}

// The straight twisted yarn in 3D, marched directly: what the table's walks turn back to
// the slice and read from its transmittance table instead.
struct TwistedYarn {
  const YarnSection& section;
  float gamma, max_path, h;
  VolumeSample Sample(glm::vec3 q) const {
    VolumeSample sample;
    sample.extinction = gamma * FibreDensity(section, glm::vec2(q), section.twist_rate * q.z);
    sample.fibre = glm::normalize(glm::vec3(-section.twist_rate * q.y, section.twist_rate * q.x, 1.0f));
    return sample;
  }
  float ModelLength(glm::vec3 v) const { return glm::length(v); }
  float step() const { return h; }
  glm::vec2 Interval(glm::vec3 o, glm::vec3 d) const {
    // Inside the cylinder of the section's extent and |z| ≤ max_path.
    float enter = 0.0f, exit = 1e9f;
    const float a = d.x * d.x + d.y * d.y, b = o.x * d.x + o.y * d.y;
    const float c = o.x * o.x + o.y * o.y - section.extent() * section.extent();
    if (a > 1e-12f) {
      const float disc = b * b - a * c;
      if (disc <= 0.0f) return {1.0f, 0.0f};
      enter = std::max(enter, (-b - std::sqrt(disc)) / a);
      exit = std::min(exit, (-b + std::sqrt(disc)) / a);
    }
    if (d.z != 0.0f) {
      const float lo = (-max_path - o.z) / d.z, hi = (max_path - o.z) / d.z;
      enter = std::max(enter, std::min(lo, hi));
      exit = std::min(exit, std::max(lo, hi));
    }
    return {enter, exit};
  }
  // T from q towards l within max_path of q.
  float Transmittance(glm::vec3 q, glm::vec3 l) const {
    const glm::vec2 span = Interval(q, l);
    float depth = 0.0f;
    for (float s = span.x + 0.5f * h; s < std::min(span.y, max_path); s += h) depth += Sample(q + s * l).extinction * h;
    return std::exp(-depth);
  }
};

TEST(LumisliceTable, DirectionsCoverTheSphereWithBothPoles) {
  EXPECT_NEAR(glm::distance(LumisliceLightDirection(0), glm::vec3(0, 0, -1)), 0.0f, 1e-6f);
  EXPECT_NEAR(glm::distance(LumisliceLightDirection(kLumisliceDirections - 1), glm::vec3(0, 0, 1)), 0.0f, 1e-6f);
  const int equator = kLumisliceLongitudes * (kLumisliceAltitudes / 2);
  EXPECT_NEAR(glm::distance(LumisliceLightDirection(equator), glm::vec3(1, 0, 0)), 0.0f, 1e-6f);
  EXPECT_NEAR(glm::distance(LumisliceLightDirection(equator + kLumisliceLongitudes / 4), glm::vec3(0, 1, 0)), 0.0f,
              1e-6f);
}

// Light in the section's plane crosses one row of voxels: at a row's far end the table's
// T_l is e^{−γ Σρ·Δ} over the row's voxels (half its own). Left out: the two rows whose
// band holds the ply's top or bottom, where the chord along the band's centre and the
// band's mean density differ by more than the march's error.
TEST(LumisliceTable, LightStraightThroughAThinYarnTransmitsWhatTheVoxelsDensitySays) {
  const YarnSection section = SectionOf(1, 0.3f, 0.0f);
  YarnMaterial material;
  const Lumislice slice = BuildLumislice(section, material, Settings(64));
  const LumisliceLevel& level = slice.levels.front();
  const int direction = kLumisliceLongitudes * (kLumisliceAltitudes / 2);  // light along +x
  int rows = 0, translucent = 0;
  for (int y = 0; y < level.resolution; ++y) {
    const size_t row = static_cast<size_t>(y) * level.resolution;
    double sum = 0.5 * level.density[row];
    for (int x = 1; x < level.resolution; ++x) sum += level.density[row + x];
    const float centre = -section.extent() + level.voxel * (static_cast<float>(y) + 0.5f);
    if (sum == 0.0 || std::abs(std::abs(centre) - 1.0f) < 0.5f * level.voxel) continue;
    const double expected = slice.optical_density * level.voxel * sum;
    const double measured = -std::log(level.at(direction, row).a);
    EXPECT_NEAR(measured, expected, 0.03 * expected + 0.02) << "row " << y;
    ++rows;
    if (expected < 2.0) ++translucent;
  }
  EXPECT_GT(rows, 50);
  EXPECT_GT(translucent, 6);  // through the fuzz and the ply's edge light gets through
}

// What the march does between voxels: against a fine quadrature of the density along
// the light's path through the twisted yarn, oblique to the section.
TEST(LumisliceTable, LightTransmittanceFollowsTheTwistedYarnsDensity) {
  const YarnSection section = SectionOf(3, 0.2f, 30.0f);
  const glm::vec3 light = glm::normalize(glm::vec3(0.6f, -0.3f, 0.5f));
  for (const glm::vec2 p : {glm::vec2(-0.9f, 0.2f), glm::vec2(-0.3f, 0.6f), glm::vec2(0.1f, -0.95f)}) {
    const float max_path = 4.0f;
    double depth = 0.0;
    const int n = 200000;
    for (int i = 0; i < n; ++i) {
      const float s = max_path * (i + 0.5f) / n;
      const glm::vec3 q = glm::vec3(p, 0.0f) + s * light;
      if (glm::length(glm::vec2(q)) > section.extent()) break;
      depth += FibreDensity(section, glm::vec2(q), section.twist_rate * q.z) * max_path / n;
    }
    const float measured = -std::log(LumisliceLightTransmittance(section, kYarnOpticalDensity, p, light, max_path,
                                                                LumisliceMarchStep(section, 32)));
    EXPECT_NEAR(measured, kYarnOpticalDensity * depth, 0.02 * kYarnOpticalDensity * depth + 0.01)
        << p.x << ", " << p.y;
  }
}

// Eq. 11: light along the yarn through a coarse voxel (2Δ thick) passes e^{−γρ'·2Δ}, the
// geometric mean of what it passes through the two fine slices of each of the four fine
// voxels under it, (Π T_i²)^{1/4} = √(T₁T₂T₃T₄) with T_i = e^{−γρ_iΔ}. The coarse
// colour is the density-weighted mean, down to 1×1.
TEST(LumisliceTable, LevelsKeepTheTransmissionOfEq11) {
  const YarnSection section = SectionOf(2, 0.4f, 20.0f);
  YarnMaterial material;
  material.diffuse_albedo = {0.8f, 0.5f, 0.2f};
  const Lumislice slice = BuildLumislice(section, material, Settings(32));
  std::vector<int> resolutions;
  for (const LumisliceLevel& level : slice.levels) resolutions.push_back(level.resolution);
  EXPECT_EQ(resolutions, (std::vector<int>{32, 16, 8, 4, 2, 1}));
  const float gamma = slice.optical_density;
  for (size_t l = 1; l < slice.levels.size(); ++l) {
    const LumisliceLevel& fine = slice.levels[l - 1];
    const LumisliceLevel& coarse = slice.levels[l];
    EXPECT_FLOAT_EQ(coarse.voxel * coarse.resolution, fine.voxel * fine.resolution) << l;
    EXPECT_FLOAT_EQ(coarse.voxel, 2.0f * fine.voxel);
    for (size_t v = 0; v < coarse.voxel_count(); ++v) {
      const int x = 2 * static_cast<int>(v % coarse.resolution), y = 2 * static_cast<int>(v / coarse.resolution);
      double product = 1.0, weight = 0.0;
      glm::dvec4 weighted(0.0);
      for (int k = 0; k < 4; ++k) {
        const size_t f = static_cast<size_t>(y + (k >> 1)) * fine.resolution + x + (k & 1);
        // Light along the yarn crosses two fine slices for each coarse one.
        product *= std::exp(-2.0 * gamma * fine.density[f] * fine.voxel);
        weight += fine.density[f];
        weighted += glm::dvec4(fine.density[f] * fine.at(5, f));
      }
      const double coarse_t = std::exp(-gamma * coarse.density[v] * coarse.voxel);
      ASSERT_NEAR(coarse_t, std::pow(product, 0.25), 1e-5) << "level " << l << " voxel " << v;
      if (weight > 0.0) {
        const glm::dvec4 expected = weighted / weight;
        for (int c = 0; c < 4; ++c) ASSERT_NEAR(coarse.at(5, v)[c], expected[c], 1e-5) << l << " voxel " << v;
      }
    }
  }
  // A coarse level keeps the section's fibre: ρ'·(2Δ)² = Σρ·Δ² over its blocks.
  for (const LumisliceLevel& level : slice.levels) {
    double fibre = 0.0;
    for (const float rho : level.density) fibre += rho * level.voxel * level.voxel;
    double finest = 0.0;
    for (const float rho : slice.levels.front().density) {
      finest += rho * slice.levels.front().voxel * slice.levels.front().voxel;
    }
    EXPECT_NEAR(fibre, finest, 1e-4 * finest) << level.resolution;
  }
}

TEST(LumisliceTable, TheDiffuseVrfIsTheFibresShadingTimesTheLightsTransmittance) {
  const YarnSection section = SectionOf(1, 0.0f, 25.0f);
  YarnMaterial material;
  material.diffuse_albedo = {0.6f, 0.3f, 0.1f};
  const glm::vec3 albedo = FibreAlbedo(material.diffuse_albedo);
  const Lumislice slice = BuildLumislice(section, material, Settings(8));
  const LumisliceLevel& level = slice.levels.front();
  const int direction = 7 + kLumisliceLongitudes * 13;
  const glm::vec3 light = LumisliceLightDirection(direction);
  const size_t voxel = 3 * 8 + 6;
  const float cell = 2.0f * section.extent() / 8.0f;
  const glm::vec2 p(-section.extent() + 6.5f * cell, -section.extent() + 3.5f * cell);
  const glm::vec3 fibre = glm::normalize(glm::vec3(-section.twist_rate * p.y, section.twist_rate * p.x, 1.0f));
  const float t = LumisliceLightTransmittance(section, slice.optical_density, p, light,
                                                LumisliceSettings().max_light_path, LumisliceMarchStep(section, 8));
  const glm::vec3 expected = FibreDiffuseScattering(albedo, fibre, light) * t;
  EXPECT_NEAR(level.at(direction, voxel).a, t, 1e-6f);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(level.at(direction, voxel)[c], expected[c], 1e-5f) << c;
  EXPECT_GT(t, 0.01f);
  EXPECT_LT(t, 0.99f);
}

TEST(LumisliceTable, LightScatteredBetweenFibresIsWhatWalksThroughTheTwistedYarnGive) {
  const YarnSection section = SectionOf(2, 0.0f, 25.0f);
  YarnMaterial material;
  material.diffuse_albedo = {0.8f, 0.3f, 0.05f};
  const glm::vec3 albedo = FibreAlbedo(material.diffuse_albedo);
  const Lumislice slice = BuildLumislice(section, material, Settings(16, 256));
  const LumisliceLevel& level = slice.levels.front();
  // Lit from +x, slightly along the yarn; a voxel on the yarn's far side, in a ply.
  const int direction = 1 + kLumisliceLongitudes * 12;
  const glm::vec3 light = LumisliceLightDirection(direction);
  const float cell = 2.0f * section.extent() / 16.0f;
  const int vx = 4, vy = 9;
  const size_t voxel = static_cast<size_t>(vy) * 16 + vx;
  const glm::vec2 p(-section.extent() + (vx + 0.5f) * cell, -section.extent() + (vy + 0.5f) * cell);
  ASSERT_GT(level.density[voxel], 0.3f);
  const glm::vec3 fibre = glm::normalize(glm::vec3(-section.twist_rate * p.y, section.twist_rate * p.x, 1.0f));
  const glm::vec3 single = FibreDiffuseScattering(albedo, fibre, light) * level.at(direction, voxel).a;
  const glm::vec3 table = glm::vec3(level.at(direction, voxel)) - single;

  const TwistedYarn yarn{section, slice.optical_density, LumisliceSettings().max_light_path,
                         LumisliceMarchStep(section, 16)};
  const std::vector<YarnMaterial> materials{material};
  RandomStream random(11, RandomStream::kFibreWalk, 0);
  glm::vec3 walked(0.0f);
  constexpr int kWalks = 20000;
  for (int i = 0; i < kWalks; ++i) {
    WalkFibres(yarn, materials, glm::vec3(p, 0.0f), yarn.Sample(glm::vec3(p, 0.0f)), random,
               [&](glm::vec3 q, const VolumeSample& at, glm::vec3 throughput) {
                 const glm::vec3 f = FibreDiffuseScattering(albedo, at.fibre, light);
                 walked += throughput * f * yarn.Transmittance(q, light);
               });
  }
  walked /= static_cast<float>(kWalks);
  // In the shadow of the yarn's near side, light yarn gets most of its light scattered.
  EXPECT_GT(table.r, single.r);
  EXPECT_GT(table.r / single.r, 4.0f * table.b / single.b);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(table[c], walked[c], 0.12f * walked[c] + 1e-4f) << c;
}

TEST(LumisliceTable, ResolutionMustBeAPowerOfTwoInRange) {
  const YarnSection section = SectionOf(2, 0.0f, 0.0f);
  for (const int resolution : {0, 4, 12, 512}) {
    try {
      BuildLumislice(section, YarnMaterial(), Settings(resolution));
      FAIL() << resolution;
    } catch (const Error& error) {
      EXPECT_NE(std::string(error.what()).find("resolution"), std::string::npos) << error.what();
    }
  }
}

}  // namespace
}  // namespace loom
