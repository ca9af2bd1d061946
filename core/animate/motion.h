#pragma once
// A prescribed linear motion of a collider or a pinned loop: still until
// `start`, then at `velocity` until `end`, then still again (times in seconds
// from the animation's start). Enough for the paper's animations: a ball thrown
// at a scarf, a scarf's ends pulled apart and let go.

#include <glm/glm.hpp>

namespace loom::animate {

struct Motion {
  glm::vec3 velocity{0.0f};
  double start = 0.0, end = 0.0;

  // How far it has moved by time t.
  glm::vec3 Displacement(double t) const {
    const double moving = glm::clamp(t, start, glm::max(start, end)) - start;
    return velocity * static_cast<float>(moving);
  }
  // Its velocity at time t.
  glm::vec3 Velocity(double t) const { return t >= start && t < end ? velocity : glm::vec3(0.0f); }
};

}  // namespace loom::animate
