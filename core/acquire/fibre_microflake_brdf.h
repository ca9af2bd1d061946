#pragma once
// The fibre-microflake yarn BRDF: the woven-fabric shading model of Jin et al. 2022 as
// the neural woven paper writes it (Chen et al. 2024, §3.1 eq. 1–2), on Loom's yarn
// surfaces, RGB,
//
//   f_r(l, v) = k_s D(h) G(l, v) / (4 μ_l μ_v) + w k_d ⟨l·n_p⟩ / (π ⟨l·n⟩) + (1 − w) k_d / π,
//   D(h) = 1 / (π α q²), q = hᵀS⁻¹h,   G = (1 − e^{−Tρ(Λ_l + Λ_v)}) / (Λ_l + Λ_v),
//   Λ(ω) = σ(ω)/μ_ω, σ(ω) = √(ωᵀSω),   S = Rᵀ diag(1, 1, α²) R with R taking t_p to z,
//
// μ_ω = ω·n with n the yarn surface's shading normal (the layer the paper's surface is),
// (n_p, t_p) the ply frame: n and the twisted fibre direction with their heights scaled
// by β. How the paper's flat surface maps onto Loom's yarn geometry, and the energy
// bounds: docs/yarn_shading.md.
//
// Transmission (light behind the layer, μ_l < 0; docs/yarn_shading.md "Light through
// the yarn"): the same layer's single scattering towards the other side (SpongeCake,
// Wang et al. 2022, which Zhu et al. 2023 and the neural paper's data build on) and a
// diffuse share t of k_d passed through instead of reflected,
//
//   f_t(l, v) = k_s D(h) (e^{−TρΛ_l} − e^{−TρΛ_v}) / (4 |μ_l| μ_v (Λ_v − Λ_l)) + t k_d / π,
//
// Λ_l = σ(l)/|μ_l|, h = (l + v)/|l + v|; the diffuse reflection above is then (1 − t)
// times the paper's. The unscattered (delta) part e^{−TρΛ_l} is left out, as the
// neural paper leaves it out.
//
// All vectors in tile coordinates (z is the cloth's normal). f_r is zero unless l is
// above n's horizon, f_t unless it is below; a v below the horizon takes the limit
// μ_v → 0⁺ in both.

#include <glm/glm.hpp>

#include "core/fabric/fabric_tile.h"

namespace loom {

// Tρ, the layer's density times thickness: "always assigned a value of 2 for fabrics".
inline constexpr float kMicroflakeOpticalDepth = 2.0f;

// The roughness the BRDF uses is at least this: a narrower lobe than any direction grid
// resolves, and far enough from 0 that 1/α² and 1/(πα) stay finite in float.
inline constexpr float kMinMicroflakeRoughness = 1e-4f;

// D(h) and σ(ω) of a fibre-like SGGX distribution with unit axis `fibre` and roughness α.
float FibreMicroflakeD(glm::vec3 h, glm::vec3 fibre, float alpha);
float FibreMicroflakeSigma(glm::vec3 w, glm::vec3 fibre, float alpha);

// The ply frame of a surface with unit normal n and yarn direction `tangent` (made
// perpendicular to n here): both with their z scaled by β as a height field's slopes
// are (normals by 1/β, directions by β), unit. `has_fibre` is false where no fibre
// direction is left (a tangent along n or zero, or a vertical one flattened by β = 0);
// a normal flattened to nothing (β = 0 on a vertical wall) stays n.
struct PlyFrame {
  glm::vec3 normal{};
  glm::vec3 fibre{};
  bool has_fibre = false;
};
PlyFrame ScaledPlyFrame(glm::vec3 normal, glm::vec3 tangent, float height_scale);

class FibreMicroflakeBrdf {
 public:
  explicit FibreMicroflakeBrdf(const YarnMaterial& material);

  // f_r and f_t for unit n, l, v; without a fibre direction the specular terms are
  // left out.
  glm::vec3 Evaluate(glm::vec3 normal, glm::vec3 tangent, glm::vec3 l, glm::vec3 v) const;
  glm::vec3 Transmit(glm::vec3 normal, glm::vec3 tangent, glm::vec3 l, glm::vec3 v) const;
  static constexpr bool kTransmits = true;

  // (1 − t) k_d/π: what indirect (diffuse inter-reflected) light is reflected by.
  glm::vec3 diffuse() const { return diffuse_; }

 private:
  glm::vec3 diffuse_;      // (1 − t) k_d / π
  glm::vec3 transmitted_;  // t k_d / π
  glm::vec3 specular_;     // k_s
  float alpha_;
  float height_scale_;
  float blend_;
};

}  // namespace loom
