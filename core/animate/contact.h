#pragma once
// Where a point stands against a collider's surface: its signed distance and the
// surface's outward normal at the nearest point (core/animate/collider.h).

#include <glm/glm.hpp>

namespace loom::animate {

struct Contact {
  float distance = 0.0f;               // signed: negative inside the solid
  glm::vec3 normal{0.0f, 0.0f, 1.0f};  // outward, unit
};

}  // namespace loom::animate
