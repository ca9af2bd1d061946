#include "core/acquire/volume_radiance.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/constants.hpp>

#include "core/acquire/fibre_walk.h"
#include "core/acquire/kajiya_kay_brdf.h"

namespace loom {
namespace {

// The least |l.z| of a transmittance grid's light (a 0.06° elevation).
constexpr float kMinLightZ = 1e-3f;

}  // namespace

glm::vec3 FibreScattering(const YarnMaterial& material, glm::vec3 fibre, glm::vec3 l, glm::vec3 v) {
  const float cos_l = std::clamp(glm::dot(fibre, l), -1.0f, 1.0f);
  const float cos_v = std::clamp(glm::dot(fibre, v), -1.0f, 1.0f);
  const float sin_l = std::sqrt(1.0f - cos_l * cos_l);
  const float sin_v = std::sqrt(1.0f - cos_v * cos_v);
  const float psi = std::clamp(sin_l * sin_v - cos_l * cos_v, 0.0f, 1.0f);
  const float exponent = std::max(material.specular_exponent, 0.0f);
  return FibreDiffuseScattering(FibreAlbedo(material.diffuse_albedo), fibre, l) +
         2.0f * material.specular_albedo * KajiyaKayNormalisation(exponent) * std::pow(psi, exponent);
}

glm::vec2 SlabInterval(const YarnVolume& volume, glm::vec3 origin, glm::vec3 direction) {
  if (direction.z == 0.0f) {
    if (origin.z < volume.z_min() || origin.z > volume.z_max()) return {1.0f, 0.0f};
    return {0.0f, kMaxHorizontalTiles / std::max(glm::length(glm::vec2(direction)), 1e-6f)};
  }
  const float a = (volume.z_min() - origin.z) / direction.z, b = (volume.z_max() - origin.z) / direction.z;
  const float horizontal = kMaxHorizontalTiles / std::max(glm::length(glm::vec2(direction)), 1e-6f);
  return {std::max(std::min(a, b), 0.0f), std::min(std::max(a, b), horizontal)};
}

float VolumeTransmittance(const YarnVolume& volume, glm::vec3 origin, glm::vec3 direction, float jitter) {
  return MarchVolume(volume, origin, direction, jitter, [](const VolumeStep&) {});
}


LightTransmittance::LightTransmittance(const YarnVolume& volume, glm::vec3 light) : light_(light) {
  // A light along the slab: its columns would never cross it.
  if (std::abs(light_.z) < kMinLightZ) light_ = glm::normalize(glm::vec3(glm::vec2(light_), std::copysign(kMinLightZ, light_.z)));
  const float spacing = kTransmittanceNodeSteps * volume.step();
  const int across = std::max(2, static_cast<int>(std::ceil(1.0f / spacing)));
  const int levels = std::max(2, static_cast<int>(std::ceil((volume.z_max() - volume.z_min()) / spacing)) + 1);
  size_ = {across, across, levels};
  face_ = light.z > 0.0f ? volume.z_max() : volume.z_min();
  z_min_ = volume.z_min();
  z_step_ = (volume.z_max() - volume.z_min()) / static_cast<float>(levels - 1);
  values_.assign(column_count() * levels, glm::vec2(1.0f, 0.0f));
}

void LightTransmittance::MarchColumns(const YarnVolume& volume, size_t first, size_t count) {
  const float h = volume.step();
  const float length_scale = volume.ModelLength(light_) * h;
  const float cutoff = -std::log(kMinVolumeTransmittance);
  for (size_t column = first; column < std::min(first + count, column_count()); ++column) {
    glm::vec2* levels = &values_[column * size_.z];
    const glm::vec3 base(static_cast<float>(column % size_.x) / size_.x, static_cast<float>(column / size_.x) / size_.y, face_);
    // Levels in the order the column reaches them, and the optical depth as it goes.
    const int first_level = light_.z > 0.0f ? size_.z - 1 : 0, step_level = light_.z > 0.0f ? -1 : 1;
    float depth = 0.0f, previous_depth = 0.0f;
    int level = first_level;
    for (int k = 0; level >= 0 && level < size_.z; ++k) {
      // Steps are midpoints: depth covers [0, (k + 1) h] after step k.
      const float s_end = static_cast<float>(k + 1) * h;
      previous_depth = depth;
      if (depth < cutoff) {
        const glm::vec3 p = base - light_ * (static_cast<float>(k) + 0.5f) * h;
        depth += volume.Sample(p).extinction * length_scale;
      }
      // Every level this step crossed: interpolate the depth within the step.
      while (level >= 0 && level < size_.z) {
        const float s_level = (face_ - (z_min_ + z_step_ * static_cast<float>(level))) / light_.z;
        if (s_level > s_end) break;
        const float t = std::clamp((s_level - (s_end - h)) / h, 0.0f, 1.0f);
        const float d = previous_depth + t * (depth - previous_depth);
        levels[level] = d < cutoff ? glm::vec2(std::exp(-d), d) : glm::vec2(0.0f, cutoff);
        level += step_level;
      }
    }
  }
}

float LightTransmittance::operator()(glm::vec3 p) const {
  // The column through p: from p towards the light, up to the face.
  const float z = std::clamp(p.z, z_min_, z_min_ + z_step_ * static_cast<float>(size_.z - 1));
  const glm::vec2 base = glm::vec2(p) + glm::vec2(light_) * ((face_ - z) / light_.z);
  const glm::vec2 grid((base.x - std::floor(base.x)) * size_.x, (base.y - std::floor(base.y)) * size_.y);
  const float level = (z - z_min_) / z_step_;
  const glm::ivec2 cell = glm::min(glm::ivec2(glm::floor(grid)), glm::ivec2(size_) - 1);
  const int low = std::min(static_cast<int>(level), size_.z - 2);
  const glm::vec3 f(grid - glm::vec2(cell), level - static_cast<float>(low));
  glm::vec2 result(0.0f);
  for (int corner = 0; corner < 8; ++corner) {
    const glm::ivec3 o(corner & 1, (corner >> 1) & 1, corner >> 2);
    const size_t column = static_cast<size_t>((cell.y + o.y) % size_.y) * size_.x + (cell.x + o.x) % size_.x;
    const float w = (o.x ? f.x : 1 - f.x) * (o.y ? f.y : 1 - f.y) * (o.z ? f.z : 1 - f.z);
    result += w * values_[column * size_.z + low + o.z];
  }
  // Interpolated T overestimates and e^(−interpolated τ) underestimates (e^(−τ) is convex):
  // their geometric mean.
  if (result.x <= 0.0f || result.y >= -std::log(kMinVolumeTransmittance)) return 0.0f;
  return std::exp(0.5f * (std::log(result.x) - result.y));
}

}  // namespace loom
