#include "core/acquire/volume_radiance.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/constants.hpp>

#include "core/acquire/kajiya_kay_brdf.h"

namespace loom {

glm::vec3 FibreScattering(const YarnMaterial& material, glm::vec3 fibre, glm::vec3 l, glm::vec3 v) {
  const float cos_l = std::clamp(glm::dot(fibre, l), -1.0f, 1.0f);
  const float cos_v = std::clamp(glm::dot(fibre, v), -1.0f, 1.0f);
  const float sin_l = std::sqrt(1.0f - cos_l * cos_l);
  const float sin_v = std::sqrt(1.0f - cos_v * cos_v);
  const float psi = std::clamp(sin_l * sin_v - cos_l * cos_v, 0.0f, 1.0f);
  const float exponent = std::max(material.specular_exponent, 0.0f);
  return 2.0f * (material.diffuse_albedo * glm::one_over_pi<float>() * sin_l +
                 material.specular_albedo * KajiyaKayNormalisation(exponent) * std::pow(psi, exponent));
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

}  // namespace loom
