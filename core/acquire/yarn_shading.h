#pragma once
// The yarn material's BRDF (issue 3 "Yarn shading"): Lambertian diffuse plus a
// Kajiya–Kay fibre lobe about the yarn tangent, RGB,
//
//   f_r(l, v) = ρ_d/π + ρ_s · N(p) · ψ^p,   ψ = max(0, sin α_l · sin α_v − cos α_l · cos α_v),
//
// with cos α_l = t·l and cos α_v = t·v, t the unit fibre direction in the surface
// (the yarn tangent made perpendicular to the normal n), l and v unit vectors towards
// the light and the viewer. ψ is the cosine of the angle between v and the cone of
// mirror directions t·r = −t·l that a fibre reflects l into, so the lobe peaks
// (ψ = 1) on that cone; p is YarnMaterial::specular_exponent.
//
// Normalisation (why the lobe is energy-plausible). Write v by its angle α to t
// and its azimuth β about t, measured from n; with t ⟂ n, cos θ_v = v·n = sin α cos β
// and dω = sin α dα dβ, and ψ depends on α only. So for every l
//   ∫_{H(n)} ψ^p cos θ_v dω = ∫₀^π ψ(α)^p sin²α dα · ∫_{−π/2}^{π/2} cos β dβ
//                           ≤ 2 ∫_{−π/2}^{π/2} cos^p x dx = 2 · I(p),
//   I(p) = √π · Γ((p+1)/2) / Γ(p/2 + 1),
// and N(p) = 1 / (2 · I(p)) makes the lobe's directional albedo at most 1. The bound
// is tight: for l ⟂ t the albedo is I(p+2)/I(p) = (p+1)/(p+2). The material's albedo
// is then at most ρ_d + ρ_s ≤ 1 (the spec validator enforces the sum). Pointwise,
// under unit irradiance the reflected radiance f_r · cos θ_l exceeds the white
// Lambertian bound cos θ_l/π (with ρ_d = 1 − ρ_s) by at most the specular share
// ρ_s · max(0, N(p) − 1/π) · cos θ_l.
//
// The BRDF is zero unless both l and v are above the shading normal's horizon.

#include <glm/glm.hpp>

#include "core/fabric/fabric_tile.h"

namespace loom {

// N(p) above; p ≥ 0. N(0) = 1/(2π), N(1) = 1/4, N(2) = 1/π; N grows like √(p/8π).
float KajiyaKayNormalisation(float exponent);

class YarnBrdf {
 public:
  explicit YarnBrdf(const YarnMaterial& material);

  // f_r for unit n, l, v. `tangent` is made perpendicular to n here; one along n
  // or zero (a degenerate mesh) gives no fibre direction, and the lobe is left out.
  glm::vec3 Evaluate(glm::vec3 normal, glm::vec3 tangent, glm::vec3 l, glm::vec3 v) const;

  // ρ_d/π: the part that indirect (diffuse inter-reflected) light is reflected by.
  glm::vec3 diffuse() const { return diffuse_; }

 private:
  glm::vec3 diffuse_;   // ρ_d / π
  glm::vec3 specular_;  // ρ_s · N(p)
  float exponent_;
};

}  // namespace loom
