#include "core/acquire/fibre_walk.h"

#include <algorithm>
#include <glm/gtc/constants.hpp>

namespace loom {

glm::vec3 FibreAlbedo(glm::vec3 diffuse_albedo) {
  glm::vec3 albedo;
  for (int c = 0; c < 3; ++c) {
    const float a = std::clamp(diffuse_albedo[c], 0.0f, 1.0f);
    const float root = 4.09712f + 4.20863f * a - std::sqrt(9.59217f + 41.6808f * a + 17.7126f * a * a);
    albedo[c] = std::clamp(1.0f - root * root, 0.0f, 1.0f);
  }
  return albedo;
}

glm::vec3 FibreDiffuseScattering(glm::vec3 fibre_albedo, glm::vec3 fibre, glm::vec3 l) {
  const float sin_l = glm::length(glm::cross(fibre, l));
  return fibre_albedo * (sin_l / (glm::pi<float>() * glm::pi<float>()));
}

glm::vec3 UniformSphereDirection(RandomStream& random) {
  const float z = 1.0f - 2.0f * random.Uniform();
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  const float phi = glm::two_pi<float>() * random.Uniform();
  return {r * std::cos(phi), r * std::sin(phi), z};
}

}  // namespace loom
