#pragma once
// A solid a knit cloth falls on (the lumislice paper §4.1.2: "other objects"):
// a plane, a sphere, a box or a closed mesh, as a signed distance with the
// outward normal, which is what the thickness force field and friction need of
// it, moved rigidly (without turning) along a Motion or, for a free ball, by the
// simulation (core/animate/knit_simulation.h).

#include <glm/glm.hpp>
#include <memory>

#include "core/animate/contact.h"
#include "core/animate/motion.h"

namespace loom::animate {

class MeshDistance;

class Collider {
 public:
  // The half-space below the plane through `point` with outward `normal`.
  static Collider Plane(glm::vec3 point, glm::vec3 normal);
  static Collider Sphere(glm::vec3 centre, float radius);
  // An axis-aligned box.
  static Collider Box(glm::vec3 centre, glm::vec3 half_extent);
  // A closed mesh (shared: colliders are copied).
  static Collider Mesh(std::shared_ptr<const MeshDistance> mesh);

  // The collider moving along `motion` from where it was made.
  Collider Moving(const Motion& motion) const;

  // Its surface nearest p when it has moved by `displacement` from where it was made.
  Contact Nearest(glm::vec3 p, glm::vec3 displacement) const;
  const Motion& motion() const { return motion_; }
  bool sphere() const { return kind_ == Kind::kSphere; }
  // Where it was made: a sphere's or a box's centre, a point of a plane (a mesh:
  // the origin of its vertices).
  glm::vec3 centre() const { return centre_; }
  // A sphere's radius (0 for the others).
  float radius() const { return kind_ == Kind::kSphere ? extent_.x : 0.0f; }

 private:
  enum class Kind { kPlane, kSphere, kBox, kMesh };
  Kind kind_ = Kind::kPlane;
  glm::vec3 centre_{0.0f};
  glm::vec3 extent_{0.0f};  // plane: unit normal; sphere: radius in x; box: half extents
  std::shared_ptr<const MeshDistance> mesh_;
  Motion motion_;
};

}  // namespace loom::animate
