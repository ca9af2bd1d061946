#pragma once
// The per-texel reflectance model of Daubert 2001 §3 (eq. 1–2): a Lafortune BRDF
// with a diffuse term and up to three generalised cosine lobes, every parameter
// RGB, evaluated in the texel's local frame:
//
//   f_1(l, v) = l_z · (ρ + Σ_i [C_x,i l_x v_x + C_y,i l_y v_y + C_z,i l_z v_z]^{N_i}),
//
// with [a]^N = 0 for a ≤ 0. The per-view lookup table T(v) of eq. 1 multiplies
// f_1 per channel and lives beside the model (core/fit/texel_fit.h), since it is a
// table over the stored view directions, not a function of parameters.
//
// What f_1 approximates. Acquisition lights every sample with a directional light
// of unit irradiance at normal incidence (core/acquire/acquisition.h), so a
// radiance sample is r(l, v) = f_r(l, v) · cos θ_l. The factor l_z (clamped at 0:
// light from below the texel's horizon reflects nothing) is that cosine w.r.t. the
// texel's average normal, so T · f_1 is fitted to the radiance samples as stored,
// and ρ + Σ lobes is a BRDF: a white Lambertian texel has ρ = 1/π.
//
// The channels are independent: channel c of f_1 depends only on channel c of
// every parameter. Fitting exploits this (three scalar fits per texel), and
// LafortuneChannel below is the one scalar formula shared by Evaluate and by any
// fitting code that needs it for other number types (automatic differentiation).

#include <array>
#include <cstdint>
#include <glm/glm.hpp>

namespace loom {

inline constexpr uint32_t kMaxLafortuneLobes = 3;

// The products l_k v_k of a light and view direction in the local frame: the lobe
// argument is their dot product with (C_x, C_y, C_z). Fitting precomputes them
// once per sample, as they do not depend on the parameters.
struct LobeArgument {
  double x = 0, y = 0, z = 0;
};

inline LobeArgument MakeLobeArgument(glm::vec3 l, glm::vec3 v) {
  return {double{l.x} * v.x, double{l.y} * v.y, double{l.z} * v.z};
}

// ρ + Σ_i [C_i · a]^{N_i} for one channel, the parameters packed as
// x = {ρ, C_x,1, C_y,1, C_z,1, N_1, C_x,2, …} (1 + 4·lobes values). Templated on
// the number type so automatic differentiation sees the same formula; callers
// multiply by l_z (and T).
template <typename T>
T LafortuneChannel(const T* x, uint32_t lobes, const LobeArgument& a) {
  T sum = x[0];
  for (uint32_t i = 0; i < lobes; ++i) {
    const T* lobe = x + 1 + 4 * i;
    const T dot = lobe[0] * a.x + lobe[1] * a.y + lobe[2] * a.z;
    if (dot > T(0)) {
      using std::pow;
      sum += pow(dot, lobe[3]);
    }
  }
  return sum;
}

struct LafortuneLobe {
  glm::vec3 cx{0.0f}, cy{0.0f}, cz{0.0f};
  // With C = 0 the lobe is off whatever N is; 1 keeps an unused lobe well defined.
  glm::vec3 n{1.0f};
};

struct LafortuneBrdf {
  glm::vec3 rho{0.0f};
  std::array<LafortuneLobe, kMaxLafortuneLobes> lobes{};
  // Lobes beyond lobe_count are ignored; a fit that fell back to fewer lobes keeps
  // lobe_count and zeroes the lobes it dropped, so every texel of a fabric has the
  // same layout.
  uint32_t lobe_count = 0;

  // f_1(l, v) for unit directions in the texel's local frame (T not applied).
  glm::vec3 Evaluate(glm::vec3 light, glm::vec3 view) const;

  // Channel c packed as LafortuneChannel's x (1 + 4·lobe_count values), and back.
  void PackChannel(int c, double* x) const;
  void UnpackChannel(int c, const double* x);

  bool AllFinite() const;
};

// The texel's local frame: normal n, tangent t (⟂ n) and bitangent n × t.
// Tile-space directions map to (t·d, (n×t)·d, n·d).
class TexelFrame {
 public:
  TexelFrame(glm::vec3 normal, glm::vec3 tangent);

  glm::vec3 ToLocal(glm::vec3 direction) const {
    return {glm::dot(tangent_, direction), glm::dot(bitangent_, direction), glm::dot(normal_, direction)};
  }

 private:
  glm::vec3 normal_, tangent_, bitangent_;
};

}  // namespace loom
