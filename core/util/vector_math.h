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

}  // namespace loom
