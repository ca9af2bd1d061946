#include "core/methods/lumislice/lumislice_table.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/acquire/fibre_walk.h"
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

// The twisted yarn's fibre at section point p (yarn radii): the fibre at offset d from the
// centre line runs along T + k·(T × d).
glm::vec3 SectionFibre(const YarnSection& section, glm::vec2 p) {
  return glm::normalize(glm::vec3(-section.twist_rate * p.y, section.twist_rate * p.x, 1.0f));
}

glm::vec2 Rotate(glm::vec2 p, float angle) {
  const float c = std::cos(angle), s = std::sin(angle);
  return {c * p.x - s * p.y, s * p.x + c * p.y};
}

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

// The straight twisted yarn around a slice as a medium for fibre walks
// (core/acquire/fibre_walk.h): yarn radii, z along the yarn, |z| ≤ the light's path.
struct StraightYarnMedium {
  const YarnSection& section;
  float optical_density, max_path, h;

  VolumeSample Sample(glm::vec3 q) const {
    VolumeSample sample;
    sample.extinction = optical_density * FibreDensity(section, glm::vec2(q), section.twist_rate * q.z);
    sample.fibre = SectionFibre(section, glm::vec2(q));
    return sample;
  }
  float ModelLength(glm::vec3 v) const { return glm::length(v); }
  float step() const { return h; }
  glm::vec2 Interval(glm::vec3 origin, glm::vec3 direction) const {
    glm::vec2 span = CircleInterval(glm::vec2(origin), glm::vec2(direction), section.extent());
    if (direction.z != 0.0f) {
      const float a = (-max_path - origin.z) / direction.z, b = (max_path - origin.z) / direction.z;
      span = {std::max(span.x, std::min(a, b)), std::min(span.y, std::max(a, b))};
    }
    return span;
  }
};

// The finest level's T_l (eq. 5) per direction (outer) and voxel, read between voxel
// centres and longitudes: what a walk's event in the straight yarn receives, turned back
// to the slice (the yarn is the slice swept and turned at the twist rate). It reads the
// optical depth −ln T, nearly linear across a voxel where T falls steeply.
class SliceTransmittance {
 public:
  SliceTransmittance(const YarnSection& section, int resolution, std::vector<float> values)
      : section_(section), resolution_(resolution), values_(std::move(values)), depth_(values_.size()) {
    for (size_t i = 0; i < values_.size(); ++i) depth_[i] = -std::log(std::max(values_[i], kMinTransmittance));
  }
  float at(int direction, size_t voxel) const { return values_[direction * voxels() + voxel]; }
  // T_l at section point p for table altitude `altitude` and longitude `longitude` (in
  // table steps, any real).
  float operator()(glm::vec2 p, int altitude, float longitude) const {
    const float cell = 2.0f * section_.extent() / static_cast<float>(resolution_);
    const glm::vec2 g = glm::clamp((p + section_.extent()) / cell - 0.5f, 0.0f, static_cast<float>(resolution_ - 1));
    const glm::ivec2 low = glm::min(glm::ivec2(g), glm::ivec2(resolution_ - 2));
    const glm::vec2 f = g - glm::vec2(low);
    const float wrapped = longitude - kLumisliceLongitudes * std::floor(longitude / kLumisliceLongitudes);
    const int first = std::min(static_cast<int>(wrapped), kLumisliceLongitudes - 1);
    const float fl = wrapped - static_cast<float>(first);
    float depth = 0.0f;
    for (int corner = 0; corner < 8; ++corner) {
      const glm::ivec3 o(corner & 1, (corner >> 1) & 1, corner >> 2);
      const int direction = (first + o.z) % kLumisliceLongitudes + kLumisliceLongitudes * altitude;
      const size_t voxel = static_cast<size_t>(low.y + o.y) * resolution_ + low.x + o.x;
      const float weight = (o.x ? f.x : 1 - f.x) * (o.y ? f.y : 1 - f.y) * (o.z ? fl : 1 - fl);
      depth += weight * depth_[direction * voxels() + voxel];
    }
    return std::exp(-depth);
  }

 private:
  static constexpr float kMinTransmittance = 1e-6f;
  size_t voxels() const { return static_cast<size_t>(resolution_) * resolution_; }
  const YarnSection& section_;
  int resolution_;
  std::vector<float> values_, depth_;
};

// I_msp of the voxel at section point p per table direction: the mean over `walks` fibre
// walks of their events' light, each event turned back to the slice to read its T_l.
std::vector<glm::vec3> VoxelScattering(const StraightYarnMedium& medium, const SliceTransmittance& lit,
                                       const std::vector<glm::vec3>& lights, const YarnMaterial& material, glm::vec2 p,
                                       int walks, size_t voxel) {
  std::vector<glm::vec3> scattered(kLumisliceDirections, glm::vec3(0.0f));
  if (walks <= 0) return scattered;
  const std::vector<YarnMaterial> materials{material};
  const glm::vec3 albedo = FibreAlbedo(material.diffuse_albedo);
  RandomStream random(0, RandomStream::kFibreWalk, voxel);
  const glm::vec3 start(p, 0.0f);
  const VolumeSample at_start = medium.Sample(start);
  // An event at q, in the yarn turned back by the twist to the slice, lit through the slice.
  auto visit = [&](glm::vec3 q, const VolumeSample& at, glm::vec3 throughput) {
    const float turn = -medium.section.twist_rate * q.z;
    const glm::vec2 slice_q = Rotate(glm::vec2(q), turn);
    const glm::vec3 slice_fibre(Rotate(glm::vec2(at.fibre), turn), at.fibre.z);
    const float shift = turn * kLumisliceLongitudes / (2.0f * kPi);
    for (int d = 0; d < kLumisliceDirections; ++d) {
      const glm::vec3 slice_l(Rotate(glm::vec2(lights[d]), turn), lights[d].z);
      const float t = lit(slice_q, d / kLumisliceLongitudes, static_cast<float>(d % kLumisliceLongitudes) + shift);
      scattered[d] += throughput * FibreDiffuseScattering(albedo, slice_fibre, slice_l) * t;
    }
  };
  for (int walk = 0; walk < walks; ++walk) WalkFibres(medium, materials, start, at_start, random, visit);
  for (glm::vec3& light : scattered) light /= static_cast<float>(walks);
  return scattered;
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
  const float step = LumisliceMarchStep(section, resolution);
  // Eq. 5's T_l per direction and voxel, then the walks (each voxel's take longer).
  constexpr double kTransmittanceShare = 0.2;
  std::vector<float> transmittance(static_cast<size_t>(kLumisliceDirections) * voxels);
  ParallelFor(
      kLumisliceDirections, settings.threads,
      [&](size_t direction, unsigned) {
        const glm::vec3 light = LumisliceLightDirection(static_cast<int>(direction));
        for (size_t voxel = 0; voxel < voxels; ++voxel) {
          transmittance[direction * voxels + voxel] =
              LumisliceLightTransmittance(section, slice.optical_density, VoxelCentre(section, resolution, voxel),
                                          light, settings.max_light_path, step);
        }
      },
      [&](size_t done) {
        if (progress) progress(kTransmittanceShare * static_cast<double>(done) / kLumisliceDirections);
      });
  const SliceTransmittance lit(section, resolution, std::move(transmittance));
  const StraightYarnMedium medium{section, slice.optical_density, settings.max_light_path, step};
  std::vector<glm::vec3> lights(kLumisliceDirections);
  for (int d = 0; d < kLumisliceDirections; ++d) lights[d] = LumisliceLightDirection(d);
  const glm::vec3 albedo = FibreAlbedo(material.diffuse_albedo);
  ParallelFor(
      voxels, settings.threads,
      [&](size_t voxel, unsigned) {
        const glm::vec2 p = VoxelCentre(section, resolution, voxel);
        const glm::vec3 fibre = SectionFibre(section, p);
        // An empty voxel's colour is never seen (its opacity is 0): no walks.
        const int walks = finest.density[voxel] > 0.0f ? settings.walks : 0;
        const std::vector<glm::vec3> scattered = VoxelScattering(medium, lit, lights, material, p, walks, voxel);
        for (int d = 0; d < kLumisliceDirections; ++d) {
          const float t = lit.at(d, voxel);
          const glm::vec3 single = FibreDiffuseScattering(albedo, fibre, lights[d]) * t;
          finest.vrf[d * voxels + voxel] = glm::vec4(single + scattered[d], t);
        }
      },
      [&](size_t done) {
        if (progress) progress(kTransmittanceShare + (1.0 - kTransmittanceShare) * static_cast<double>(done) / voxels);
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
