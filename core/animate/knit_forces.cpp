#include "core/animate/knit_forces.h"

#include <cmath>
#include <limits>

#include "core/util/error.h"

namespace loom::animate {
namespace {

// The angle between unit vectors p̂ and q̂, and its gradients with respect to the
// ends of p and q (their tails held): −perp(q̂ to p̂)/|p| and −perp(p̂ to q̂)/|q|.
struct AngleGradient {
  float angle = 0.0f;
  glm::vec3 d_p{0.0f}, d_q{0.0f};
  bool defined = false;
};

AngleGradient AngleBetween(glm::vec3 p, glm::vec3 q) {
  AngleGradient g;
  const float pp = glm::dot(p, p), qq = glm::dot(q, q);
  if (!(pp > 0.0f) || !(qq > 0.0f)) return g;
  const float inverse_lp = 1.0f / std::sqrt(pp), inverse_lq = 1.0f / std::sqrt(qq);
  const glm::vec3 pu = p * inverse_lp, qu = q * inverse_lq;
  const float c = glm::dot(pu, qu);
  // |p̂ × q̂| = sin θ = |q̂ − cos θ p̂| = |p̂ − cos θ q̂|.
  const float s = glm::length(glm::cross(pu, qu));
  g.angle = std::atan2(s, c);
  if (s < 1e-6f) return g;
  const float inverse_s = 1.0f / s;
  g.d_p = (c * pu - qu) * (inverse_s * inverse_lp);
  g.d_q = (c * qu - pu) * (inverse_s * inverse_lq);
  g.defined = true;
  return g;
}

}  // namespace

float SpringForce(const SpringLaw& law, float rest, float length) {
  const float high = law.balance_high * rest, low = law.balance_low * rest;
  if (length > high) return law.stretch * std::expm1((length - high) / high);
  if (length < low) return -law.compress * std::expm1((low - length) / low);
  return 0.0f;
}

float SpringStiffness(const SpringLaw& law, float rest, float length) {
  const float high = law.balance_high * rest, low = law.balance_low * rest;
  if (length > high) return law.stretch / high * std::exp((length - high) / high);
  if (length < low) return law.compress / low * std::exp((low - length) / low);
  return 0.0f;
}

ThicknessField::ThicknessField(float half_thickness, float core, float strength)
    : half_thickness_(half_thickness), core_(core), strength_(strength) {
  if (!(core > 0.0f && half_thickness > core && strength > 0.0f)) {
    throw Error(ErrorCode::kInvalidArgument,
                "thickness field: needs half thickness T > core τ > 0 and "
                "strength > 0");
  }
  // Value and slope of c₅(T − d)² at τ matched by c₆e^{α/d}: α/τ² = 2/(T − τ).
  const float gap = half_thickness - core;
  alpha_ = 2.0f * core * core / gap;
  c6_ = strength * gap * gap * std::exp(-alpha_ / core);
}

float ThicknessField::operator()(float d) const {
  if (d >= half_thickness_) return 0.0f;
  if (d >= core_) return strength_ * (half_thickness_ - d) * (half_thickness_ - d);
  if (d <= 0.0f) return std::numeric_limits<float>::infinity();
  const float exponent = alpha_ / d;
  return exponent > 80.0f ? std::numeric_limits<float>::infinity() : c6_ * std::exp(exponent);
}

float ThicknessField::Slope(float d) const {
  if (d >= half_thickness_) return 0.0f;
  if (d >= core_) return -2.0f * strength_ * (half_thickness_ - d);
  if (d <= 0.0f) return -std::numeric_limits<float>::infinity();
  return -alpha_ / (d * d) * (*this)(d);
}

float ThicknessField::DistanceOf(float force) const {
  if (force <= 0.0f) return half_thickness_;
  const float at_core = strength_ * (half_thickness_ - core_) * (half_thickness_ - core_);
  if (force <= at_core) return half_thickness_ - std::sqrt(force / strength_);
  return alpha_ / std::log(force / c6_);
}

std::array<glm::vec3, 3> BendForces(glm::vec3 a, glm::vec3 b, glm::vec3 c, float constant, float arm) {
  // The turn θ between u = b − a and w = c − b: ∂θ/∂a = −∂θ/∂u, ∂θ/∂c = ∂θ/∂w.
  const AngleGradient g = AngleBetween(b - a, c - b);
  if (!g.defined) return {};
  const float scale = -constant * g.angle * arm;
  const glm::vec3 fa = scale * -g.d_p, fc = scale * g.d_q;
  return {fa, -(fa + fc), fc};
}

std::array<glm::vec3, 3> ShearForces(glm::vec3 a, glm::vec3 b, glm::vec3 c, float rest_angle, float constant,
                                     float arm) {
  const AngleGradient g = AngleBetween(a - b, c - b);
  if (!g.defined) return {};
  const float scale = -constant * (g.angle - rest_angle) * arm;
  const glm::vec3 fa = scale * g.d_p, fc = scale * g.d_q;
  return {fa, -(fa + fc), fc};
}

}  // namespace loom::animate
