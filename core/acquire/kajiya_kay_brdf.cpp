#include "core/acquire/kajiya_kay_brdf.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/constants.hpp>

namespace loom {

float KajiyaKayNormalisation(float exponent) {
  // I(p) through log-gamma: Γ itself overflows long before p reaches useful
  // exponents of a few thousand.
  const double p = std::max(exponent, 0.0f);
  const double integral = std::sqrt(glm::pi<double>()) * std::exp(std::lgamma((p + 1) / 2) - std::lgamma(p / 2 + 1));
  return static_cast<float>(1.0 / (2.0 * integral));
}

KajiyaKayBrdf::KajiyaKayBrdf(const YarnMaterial& material)
    : diffuse_(material.diffuse_albedo * glm::one_over_pi<float>()),
      specular_(material.specular_albedo * KajiyaKayNormalisation(material.specular_exponent)),
      exponent_(std::max(material.specular_exponent, 0.0f)) {}

glm::vec3 KajiyaKayBrdf::Evaluate(glm::vec3 normal, glm::vec3 tangent, glm::vec3 l, glm::vec3 v) const {
  if (!(glm::dot(normal, l) > 0.0f)) return glm::vec3(0.0f);
  // The bound on the lobe's albedo holds for a fibre lying in the surface.
  const glm::vec3 along = tangent - normal * glm::dot(normal, tangent);
  const float length2 = glm::dot(along, along);
  if (!(length2 > 1e-12f)) return diffuse_;
  const glm::vec3 t = along / std::sqrt(length2);
  // Clamped so that rounding in nearly unit inputs cannot take a square root of a
  // negative number or lift ψ above 1.
  const float cos_l = std::clamp(glm::dot(t, l), -1.0f, 1.0f);
  const float cos_v = std::clamp(glm::dot(t, v), -1.0f, 1.0f);
  const float sin_l = std::sqrt(1.0f - cos_l * cos_l);
  const float sin_v = std::sqrt(1.0f - cos_v * cos_v);
  const float psi = std::clamp(sin_l * sin_v - cos_l * cos_v, 0.0f, 1.0f);
  return diffuse_ + specular_ * std::pow(psi, exponent_);
}

}  // namespace loom
