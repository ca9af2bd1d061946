#pragma once
// A scene light as every renderer reads it, so that svbrdf (core/shaders/lights.glsl)
// and the reference shade under the same lights: a directional light's
// colour × intensity is the irradiance it brings at normal incidence; a point
// light's is its intensity, and irradiance falls off as 1 / distance².

#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>

#include "core/spec/spec_math.h"
#include "loom/v1/scene.pb.h"

namespace loom {

struct SceneLight {
  bool directional = true;
  glm::vec3 vector{};    // unit direction towards the light, or its position
  glm::vec3 radiance{};  // colour × intensity
  bool casts_shadows = false;

  // Unit direction towards the light from `position` and the irradiance it brings
  // at normal incidence there (lights.glsl's LightDirection).
  glm::vec3 Direction(glm::vec3 position, glm::vec3& irradiance) const {
    if (directional) {
      irradiance = radiance;
      return vector;
    }
    const glm::vec3 to_light = vector - position;
    const float distance2 = std::max(glm::dot(to_light, to_light), 1e-8f);
    irradiance = radiance / distance2;
    return to_light / std::sqrt(distance2);
  }
};

// `light` with defaults applied (core/spec/defaults.h).
inline SceneLight MakeSceneLight(const v1::Light& light) {
  const bool directional = light.type() != v1::LIGHT_TYPE_POINT;
  return {directional, directional ? glm::normalize(ToGlm(light.direction())) : ToGlm(light.position()),
          ToGlm(light.colour()) * light.intensity(), light.casts_shadows()};
}

}  // namespace loom
