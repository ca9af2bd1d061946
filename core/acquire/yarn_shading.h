#pragma once
// The yarn material's BRDF, whichever model the yarn's spec chose
// (YarnSpec.shading; docs/yarn_shading.md): what acquisition and the reference
// renderer shade yarn surfaces with.

#include <glm/glm.hpp>
#include <variant>

#include "core/acquire/fibre_microflake_brdf.h"
#include "core/acquire/kajiya_kay_brdf.h"
#include "core/fabric/fabric_tile.h"

namespace loom {

class YarnBrdf {
 public:
  explicit YarnBrdf(const YarnMaterial& material);

  // f_r for unit n, l, v in tile coordinates; `tangent` is the interpolated
  // (twisted) yarn direction, not necessarily unit or in the surface. Zero unless l
  // is above n's horizon; whether v sees the surface is the caller's (the hit
  // triangle's side: core/acquire/yarn_radiance.h).
  glm::vec3 Evaluate(glm::vec3 normal, glm::vec3 tangent, glm::vec3 l, glm::vec3 v) const {
    return std::visit([&](const auto& brdf) { return brdf.Evaluate(normal, tangent, l, v); }, brdf_);
  }

  // f_t for l below n's horizon (zero above it, and for a model that does not
  // transmit): light that reached the yarn from behind and leaves towards v.
  glm::vec3 Transmit(glm::vec3 normal, glm::vec3 tangent, glm::vec3 l, glm::vec3 v) const {
    return std::visit([&](const auto& brdf) { return brdf.Transmit(normal, tangent, l, v); }, brdf_);
  }
  // Whether Transmit can be non-zero: whether light behind a yarn is worth a ray.
  bool transmits() const {
    return std::visit([](const auto& brdf) { return brdf.kTransmits; }, brdf_);
  }

  // ρ_d/π: the part that indirect (diffuse inter-reflected) light is reflected by.
  glm::vec3 diffuse() const {
    return std::visit([](const auto& brdf) { return brdf.diffuse(); }, brdf_);
  }

 private:
  std::variant<KajiyaKayBrdf, FibreMicroflakeBrdf> brdf_;
};

}  // namespace loom
