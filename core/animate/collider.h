#pragma once
// A solid a knit cloth falls on (the lumislice paper §4.1.2: "other objects"):
// a plane, a sphere or a box, as a signed distance with the outward normal,
// which is what the thickness force field and friction need of it, moving
// rigidly along a Motion (without turning).

#include <glm/glm.hpp>

#include "core/animate/motion.h"

namespace loom::animate {

struct Contact {
  float distance = 0.0f;               // signed: negative inside the solid
  glm::vec3 normal{0.0f, 0.0f, 1.0f};  // outward, unit
};

class Collider {
 public:
  // The half-space below the plane through `point` with outward `normal`.
  static Collider Plane(glm::vec3 point, glm::vec3 normal);
  static Collider Sphere(glm::vec3 centre, float radius);
  // An axis-aligned box.
  static Collider Box(glm::vec3 centre, glm::vec3 half_extent);

  // The collider moving along `motion` from where it was made.
  Collider Moving(const Motion& motion) const;

  // Its surface nearest p at time t (seconds).
  Contact Nearest(glm::vec3 p, double t) const;
  // Its velocity at time t.
  glm::vec3 Velocity(double t) const { return motion_.Velocity(t); }

 private:
  enum class Kind { kPlane, kSphere, kBox };
  Kind kind_ = Kind::kPlane;
  glm::vec3 centre_{0.0f};
  glm::vec3 extent_{0.0f};  // plane: unit normal; sphere: radius in x; box: half extents
  Motion motion_;
};

}  // namespace loom::animate
