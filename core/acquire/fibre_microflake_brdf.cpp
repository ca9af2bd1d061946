#include "core/acquire/fibre_microflake_brdf.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/constants.hpp>

namespace loom {
namespace {

glm::vec3 UnitOr(glm::vec3 v, glm::vec3 fallback, bool& ok) {
  const float length2 = glm::dot(v, v);
  ok = length2 > 1e-12f;
  return ok ? v / std::sqrt(length2) : fallback;
}

}  // namespace

// S has eigenvalue α² along the fibre and 1 across it, S⁻¹ 1/α² and 1, so for a unit
// vector ω with c = ω·fibre: ωᵀSω = 1 − (1 − α²)c², ωᵀS⁻¹ω = 1 + (1/α² − 1)c².
float FibreMicroflakeD(glm::vec3 h, glm::vec3 fibre, float alpha) {
  const float c = glm::dot(h, fibre);
  const float q = 1.0f + (1.0f / (alpha * alpha) - 1.0f) * c * c;
  return 1.0f / (glm::pi<float>() * alpha * q * q);
}

float FibreMicroflakeSigma(glm::vec3 w, glm::vec3 fibre, float alpha) {
  const float c = glm::dot(w, fibre);
  return std::sqrt(std::max(1.0f - (1.0f - alpha * alpha) * c * c, alpha * alpha));
}

PlyFrame ScaledPlyFrame(glm::vec3 normal, glm::vec3 tangent, float height_scale) {
  PlyFrame frame;
  bool ok = false;
  frame.normal = UnitOr(glm::vec3(height_scale * normal.x, height_scale * normal.y, normal.z), normal, ok);
  bool in_surface = false;
  const glm::vec3 along = UnitOr(tangent - normal * glm::dot(normal, tangent), glm::vec3(0.0f), in_surface);
  if (!in_surface) return frame;
  frame.fibre = UnitOr(glm::vec3(along.x, along.y, height_scale * along.z), glm::vec3(0.0f), frame.has_fibre);
  return frame;
}

FibreMicroflakeBrdf::FibreMicroflakeBrdf(const YarnMaterial& material)
    : diffuse_(material.diffuse_albedo * ((1.0f - material.diffuse_transmission) * glm::one_over_pi<float>())),
      transmitted_(material.diffuse_albedo * (material.diffuse_transmission * glm::one_over_pi<float>())),
      specular_(material.specular_albedo),
      alpha_(std::max(material.roughness, kMinMicroflakeRoughness)),
      height_scale_(material.height_scale),
      blend_(material.lambert_blend) {}

glm::vec3 FibreMicroflakeBrdf::Evaluate(glm::vec3 normal, glm::vec3 tangent, glm::vec3 l, glm::vec3 v) const {
  const float mu_l = glm::dot(normal, l);
  if (!(mu_l > 0.0f)) return glm::vec3(0.0f);
  const PlyFrame ply = ScaledPlyFrame(normal, tangent, height_scale_);
  const float ply_cosine = std::max(glm::dot(l, ply.normal), 0.0f);
  const glm::vec3 diffuse = diffuse_ * (blend_ * ply_cosine / mu_l + (1.0f - blend_));
  bool has_half = false;
  const glm::vec3 h = UnitOr(l + v, glm::vec3(0.0f), has_half);
  if (!ply.has_fibre || !has_half) return diffuse;
  // G/μ_v = (1 − e^{−TρΛ}) / (Λμ_v) with Λμ_v = σ_l μ_v/μ_l + σ_v: finite as μ_v → 0⁺, where
  // it is 1/σ_v, the value a view below n's horizon (a silhouette's) takes.
  const float mu_v = std::max(glm::dot(normal, v), 0.0f);
  const float sigma_l = FibreMicroflakeSigma(l, ply.fibre, alpha_);
  const float sigma_v = FibreMicroflakeSigma(v, ply.fibre, alpha_);
  const float lambda_mu_v = sigma_l * mu_v / mu_l + sigma_v;
  const float attenuation_over_mu_v =
      mu_v > 0.0f ? -std::expm1(-kMicroflakeOpticalDepth * lambda_mu_v / mu_v) / lambda_mu_v : 1.0f / sigma_v;
  return diffuse + specular_ * (FibreMicroflakeD(h, ply.fibre, alpha_) * attenuation_over_mu_v / (4.0f * mu_l));
}

glm::vec3 FibreMicroflakeBrdf::Transmit(glm::vec3 normal, glm::vec3 tangent, glm::vec3 l, glm::vec3 v) const {
  const float mu_l = -glm::dot(normal, l);
  if (!(mu_l > 0.0f)) return glm::vec3(0.0f);
  bool has_half = false;
  const glm::vec3 h = UnitOr(l + v, glm::vec3(0.0f), has_half);
  const PlyFrame ply = ScaledPlyFrame(normal, tangent, height_scale_);
  if (!ply.has_fibre || !has_half) return transmitted_;
  // (e^{−a} − e^{−b}) / ((Λ_v − Λ_l) μ_v) with a = TρΛ_l, b = TρΛ_v, written so that
  // it stays finite as b → a (the limit Tρ e^{−a}/μ_v) and as μ_v → 0⁺ (e^{−a}/σ_v).
  const float mu_v = std::max(glm::dot(normal, v), 0.0f);
  const float sigma_v = FibreMicroflakeSigma(v, ply.fibre, alpha_);
  const float a = kMicroflakeOpticalDepth * FibreMicroflakeSigma(l, ply.fibre, alpha_) / mu_l;
  float through_over_mu_v = 0.0f;
  if (mu_v > 0.0f) {
    const float b = kMicroflakeOpticalDepth * sigma_v / mu_v;
    const float x = std::abs(b - a);
    const float ratio = x > 1e-6f ? -std::expm1(-x) / x : 1.0f;  // (1 − e^{−x})/x
    through_over_mu_v = std::exp(-std::min(a, b)) * ratio * kMicroflakeOpticalDepth / mu_v;
  } else {
    through_over_mu_v = std::exp(-a) / sigma_v;
  }
  return transmitted_ + specular_ * (FibreMicroflakeD(h, ply.fibre, alpha_) * through_over_mu_v / (4.0f * mu_l));
}

}  // namespace loom
