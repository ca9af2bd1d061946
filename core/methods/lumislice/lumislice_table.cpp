#include "core/methods/lumislice/lumislice_table.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/fabric/yarn_material.h"
#include "core/fabric/yarn_volume.h"
#include "core/util/error.h"
#include "core/util/parallel_for.h"

namespace loom {
namespace {

constexpr int kProfilePhases = 16;  // the shadow profile's chords, averaged over the section's turn
constexpr int kChordSteps = 256;

constexpr float kPi = std::numbers::pi_v<float>;
// March steps per radius of the thinnest ply at least, as the volume's march (yarn_volume.cpp).
constexpr float kStepsPerPlyRadius = 6.0f;

glm::vec2 VoxelCentre(const YarnSection& section, int resolution, size_t voxel) {
  const float cell = 2.0f * section.extent() / static_cast<float>(resolution);
  const int x = static_cast<int>(voxel % resolution), y = static_cast<int>(voxel / resolution);
  return {-section.extent() + cell * (x + 0.5f), -section.extent() + cell * (y + 0.5f)};
}

// The part [enter, exit] of the ray p + s·d, s ≥ 0, inside the circle of radius r about
// the origin (empty: enter ≥ exit); all of s ≥ 0 when d has no part in the plane and p
// is inside.
glm::vec2 CircleInterval(glm::vec2 p, glm::vec2 d, float r) {
  const float a = glm::dot(d, d), b = glm::dot(p, d), c = glm::dot(p, p) - r * r;
  if (a < 1e-12f) return c <= 0.0f ? glm::vec2(0.0f, std::numeric_limits<float>::infinity()) : glm::vec2(0.0f);
  const float discriminant = b * b - a * c;
  if (discriminant <= 0.0f) return glm::vec2(0.0f);
  const float root = std::sqrt(discriminant);
  return {std::max((-b - root) / a, 0.0f), std::max((-b + root) / a, 0.0f)};
}

}  // namespace

glm::vec3 LumisliceLightDirection(int direction) {
  const int longitude = direction % kLumisliceLongitudes, altitude = direction / kLumisliceLongitudes;
  const float theta = 2.0f * kPi * static_cast<float>(longitude) / kLumisliceLongitudes;
  const float phi = -0.5f * kPi + kPi * static_cast<float>(altitude) / (kLumisliceAltitudes - 1);
  return {std::cos(phi) * std::cos(theta), std::cos(phi) * std::sin(theta), std::sin(phi)};
}

size_t Lumislice::StoredBytes() const {
  size_t halves = 0;
  for (const LumisliceLevel& level : levels) halves += level.density.size() + 4 * level.vrf.size();
  return 2 * halves;
}

float LumisliceMarchStep(const YarnSection& section, int resolution) {
  return std::min(section.ply_radius / kStepsPerPlyRadius, section.extent() / static_cast<float>(resolution));
}

float LumisliceLightTransmittance(const YarnSection& section, float optical_density, glm::vec2 p, glm::vec3 light,
                                  float max_path, float h) {
  const glm::vec2 inside = CircleInterval(p, glm::vec2(light), section.extent());
  const float begin = inside.x, end = std::min(inside.y, max_path);
  float depth = 0.0f;
  for (float s = begin + 0.5f * h; s < end + 0.5f * h; s += h) {
    const glm::vec3 q = glm::vec3(p, 0.0f) + s * light;
    depth += FibreDensity(section, glm::vec2(q), section.twist_rate * q.z) * (std::min(s + 0.5f * h, end) - (s - 0.5f * h));
  }
  return std::exp(-optical_density * depth);
}

LumisliceLevel HalveLumisliceLevel(const LumisliceLevel& fine) {
  LumisliceLevel coarse;
  coarse.resolution = fine.resolution / 2;
  coarse.voxel = 2.0f * fine.voxel;
  const size_t voxels = coarse.voxel_count();
  coarse.density.resize(voxels);
  coarse.vrf.resize(static_cast<size_t>(kLumisliceDirections) * voxels);
  auto block = [&](size_t voxel, int k) {
    const int x = 2 * static_cast<int>(voxel % coarse.resolution) + (k & 1);
    const int y = 2 * static_cast<int>(voxel / coarse.resolution) + (k >> 1);
    return static_cast<size_t>(y) * fine.resolution + x;
  };
  for (size_t voxel = 0; voxel < voxels; ++voxel) {
    float sum = 0.0f;
    for (int k = 0; k < 4; ++k) sum += fine.density[block(voxel, k)];
    coarse.density[voxel] = 0.25f * sum;
    for (int d = 0; d < kLumisliceDirections; ++d) {
      glm::vec4 weighted(0.0f), plain(0.0f);
      for (int k = 0; k < 4; ++k) {
        const glm::vec4& c = fine.at(d, block(voxel, k));
        weighted += fine.density[block(voxel, k)] * c;
        plain += c;
      }
      coarse.vrf[d * voxels + voxel] = sum > 0.0f ? weighted / sum : 0.25f * plain;
    }
  }
  return coarse;
}

std::vector<float> YarnShadowProfile(const YarnSection& section, float optical_density) {
  const float extent = section.extent();
  std::vector<float> chord(kYarnShadowProfileSamples);
  for (int k = 0; k < kYarnShadowProfileSamples; ++k) {
    const float d = extent * static_cast<float>(k) / (kYarnShadowProfileSamples - 1);
    double transmittance = 0.0;
    for (int p = 0; p < kProfilePhases; ++p) {
      const float phase = 2.0f * std::numbers::pi_v<float> * static_cast<float>(p) / kProfilePhases;
      double depth = 0.0;
      const float ds = 2.0f * extent / kChordSteps;
      for (int s = 0; s < kChordSteps; ++s) {
        depth += FibreDensity(section, {d, -extent + ds * (static_cast<float>(s) + 0.5f)}, phase) * ds;
      }
      transmittance += std::exp(-optical_density * depth);
    }
    chord[k] = static_cast<float>(transmittance / kProfilePhases);
  }
  std::vector<float> profile(kYarnShadowProfileSamples, 1.0f);
  const float centre = 1.0f - chord[0];
  if (centre <= 0.0f) return profile;
  for (int k = 0; k < kYarnShadowProfileSamples; ++k) {
    profile[k] = std::clamp(1.0f - kYarnShadowStrength * (1.0f - chord[k]) / centre, 0.0f, 1.0f);
  }
  return profile;
}

Lumislice BuildLumislice(const YarnSection& section, const YarnMaterial& material, const LumisliceSettings& settings,
                         const std::function<void(double)>& progress) {
  const int resolution = settings.resolution;
  if (resolution < 8 || resolution > 256 || (resolution & (resolution - 1)) != 0) {
    throw Error(ErrorCode::kInvalidArgument, "lumislice resolution " + std::to_string(resolution) +
                                                 ": must be a power of two in [8, 256]");
  }
  Lumislice slice;
  slice.section = section;
  slice.optical_density = kYarnOpticalDensity;
  LumisliceLevel finest;
  finest.resolution = resolution;
  finest.voxel = 2.0f * section.extent() / static_cast<float>(resolution);
  finest.density = SectionDensityGrid(section, resolution);
  const size_t voxels = finest.voxel_count();
  finest.vrf.assign(static_cast<size_t>(kLumisliceDirections) * voxels, glm::vec4(0.0f));
  const glm::vec3 diffuse = 2.0f * material.diffuse_albedo / kPi;
  const float step = LumisliceMarchStep(section, resolution);
  ParallelFor(
      kLumisliceDirections, settings.threads,
      [&](size_t direction, unsigned) {
        const glm::vec3 light = LumisliceLightDirection(static_cast<int>(direction));
        for (size_t voxel = 0; voxel < voxels; ++voxel) {
          const glm::vec2 p = VoxelCentre(section, resolution, voxel);
          // The fibre at offset d from the centre line runs along T + k·(T × d).
          const glm::vec3 fibre = glm::normalize(glm::vec3(-section.twist_rate * p.y, section.twist_rate * p.x, 1.0f));
          const float sin_l = glm::length(glm::cross(fibre, light));
          const float transmittance =
              LumisliceLightTransmittance(section, slice.optical_density, p, light, settings.max_light_path, step);
          finest.vrf[direction * voxels + voxel] = glm::vec4(diffuse * sin_l * transmittance, transmittance);
        }
      },
      [&](size_t done) {
        if (progress) progress(static_cast<double>(done) / kLumisliceDirections);
      });
  slice.levels.push_back(std::move(finest));
  while (slice.levels.back().resolution > 1) slice.levels.push_back(HalveLumisliceLevel(slice.levels.back()));
  slice.shadow_profile = YarnShadowProfile(section, slice.optical_density);
  return slice;
}

std::vector<Lumislice> BuildFabricLumislices(const v1::FabricSpec& fabric, const LumisliceSettings& settings) {
  std::vector<Lumislice> slices;
  for (const v1::YarnSpec& yarn : fabric.yarns()) {
    slices.push_back(BuildLumislice(MakeYarnSection(yarn), MakeYarnMaterial(yarn), settings));
  }
  return slices;
}

}  // namespace loom
