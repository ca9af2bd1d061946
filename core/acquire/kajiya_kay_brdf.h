#pragma once
// The Kajiya–Kay yarn BRDF: Lambertian diffuse plus a fibre lobe about the yarn
// tangent t, RGB,
//
//   f_r(l, v) = ρ_d/π + ρ_s · N(p) · ψ^p,   ψ = max(0, sin α_l · sin α_v − cos α_l · cos α_v),
//
// cos α_l = t·l, cos α_v = t·v: ψ peaks on the cone of mirror directions of the fibre.
// N(p) bounds the lobe's directional albedo by 1, so the material's is at most
// ρ_d + ρ_s (the derivation: docs/yarn_shading.md). Zero unless l is above the
// shading normal's horizon; v may be below it (the formula does not involve n·v).
// The yarn is opaque: no transmission.

#include <glm/glm.hpp>

#include "core/fabric/fabric_tile.h"

namespace loom {

// N(p) above; p ≥ 0. N(0) = 1/(2π), N(1) = 1/4, N(2) = 1/π; N grows like √(p/8π).
float KajiyaKayNormalisation(float exponent);

class KajiyaKayBrdf {
 public:
  explicit KajiyaKayBrdf(const YarnMaterial& material);

  // f_r for unit n, l, v. `tangent` is made perpendicular to n here; one along n
  // or zero (a degenerate mesh) gives no fibre direction, and the lobe is left out.
  glm::vec3 Evaluate(glm::vec3 normal, glm::vec3 tangent, glm::vec3 l, glm::vec3 v) const;
  // The yarn is opaque: no light passes through it.
  static constexpr bool kTransmits = false;
  glm::vec3 Transmit(glm::vec3, glm::vec3, glm::vec3, glm::vec3) const { return glm::vec3(0.0f); }

  // ρ_d/π: the part that indirect (diffuse inter-reflected) light is reflected by.
  glm::vec3 diffuse() const { return diffuse_; }

 private:
  glm::vec3 diffuse_;   // ρ_d / π
  glm::vec3 specular_;  // ρ_s · N(p)
  float exponent_;
};

}  // namespace loom
