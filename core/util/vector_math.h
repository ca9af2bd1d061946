#pragma once
// Small vector helpers that must never produce NaN.

#include <cmath>
#include <glm/glm.hpp>

namespace loom {

// v / |v|, or `fallback` where |v| is too small for the division to be meaningful.
inline glm::vec3 SafeNormalize(glm::vec3 v, glm::vec3 fallback) {
  const float length2 = glm::dot(v, v);
  // Squared lengths below this lose the precision a unit vector needs (and 1/√
  // of a denormal overflows); yarn meshes are far coarser.
  return length2 > 1e-24f && std::isfinite(length2) ? v / std::sqrt(length2) : fallback;
}

// A unit vector perpendicular to unit `t`.
inline glm::vec3 AnyPerpendicular(glm::vec3 t) {
  const glm::vec3 axis = std::abs(t.z) < 0.9f ? glm::vec3(0, 0, 1) : glm::vec3(1, 0, 0);
  return glm::normalize(glm::cross(glm::cross(t, axis), t));
}

}  // namespace loom
