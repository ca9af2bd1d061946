#pragma once
// A prescribed motion of a collider or a pinned loop: a sum of legs, each at a
// constant velocity between its start and end (seconds from the animation's
// start), still outside them; legs that overlap add. Enough for the paper's
// animations: a ball thrown at a scarf and back, a scarf's ends pulled apart and
// let go, a scarf's end carried over to fold it.

#include <glm/glm.hpp>
#include <vector>

namespace loom::animate {

struct MotionLeg {
  glm::vec3 velocity{0.0f};
  double start = 0.0, end = 0.0;  // end ≥ start
};

struct Motion {
  std::vector<MotionLeg> legs;

  Motion() = default;
  // One leg.
  Motion(glm::vec3 velocity, double start, double end) : legs{{velocity, start, end}} {}

  // How far it has moved by time t.
  glm::vec3 Displacement(double t) const {
    glm::vec3 moved(0.0f);
    for (const MotionLeg& leg : legs) {
      moved += leg.velocity * static_cast<float>(glm::clamp(t, leg.start, glm::max(leg.start, leg.end)) - leg.start);
    }
    return moved;
  }
  // Its velocity at time t.
  glm::vec3 Velocity(double t) const {
    glm::vec3 velocity(0.0f);
    for (const MotionLeg& leg : legs) {
      if (t >= leg.start && t < leg.end) velocity += leg.velocity;
    }
    return velocity;
  }
  // Whether every leg ends no earlier than it starts.
  bool valid() const {
    for (const MotionLeg& leg : legs) {
      if (!(leg.end >= leg.start)) return false;
    }
    return true;
  }
};

}  // namespace loom::animate
