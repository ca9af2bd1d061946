#include "core/animate/collider.h"

#include <algorithm>

#include "core/animate/mesh_distance.h"
#include "core/util/error.h"

namespace loom::animate {

Collider Collider::Plane(glm::vec3 point, glm::vec3 normal) {
  if (!(glm::length(normal) > 0.0f)) throw Error(ErrorCode::kInvalidArgument, "plane collider: zero normal");
  Collider c;
  c.kind_ = Kind::kPlane;
  c.centre_ = point;
  c.extent_ = glm::normalize(normal);
  return c;
}

Collider Collider::Sphere(glm::vec3 centre, float radius) {
  if (!(radius > 0.0f)) throw Error(ErrorCode::kInvalidArgument, "sphere collider: radius must be > 0");
  Collider c;
  c.kind_ = Kind::kSphere;
  c.centre_ = centre;
  c.extent_ = glm::vec3(radius);
  return c;
}

Collider Collider::Box(glm::vec3 centre, glm::vec3 half_extent) {
  if (!(glm::all(glm::greaterThan(half_extent, glm::vec3(0.0f))))) {
    throw Error(ErrorCode::kInvalidArgument, "box collider: half extents must be > 0");
  }
  Collider c;
  c.kind_ = Kind::kBox;
  c.centre_ = centre;
  c.extent_ = half_extent;
  return c;
}

Collider Collider::Mesh(std::shared_ptr<const MeshDistance> mesh) {
  if (!mesh) throw Error(ErrorCode::kInvalidArgument, "mesh collider: no mesh");
  Collider c;
  c.kind_ = Kind::kMesh;
  c.mesh_ = std::move(mesh);
  return c;
}

Collider Collider::Moving(const Motion& motion) const {
  if (!motion.valid()) throw Error(ErrorCode::kInvalidArgument, "collider motion: end before start");
  Collider c = *this;
  c.motion_ = motion;
  return c;
}

Contact Collider::Nearest(glm::vec3 p, glm::vec3 displacement) const {
  p -= displacement;
  switch (kind_) {
    case Kind::kPlane:
      return {glm::dot(p - centre_, extent_), extent_};
    case Kind::kSphere: {
      const glm::vec3 r = p - centre_;
      const float length = glm::length(r);
      return {length - extent_.x, length > 0.0f ? r / length : glm::vec3(0.0f, 0.0f, 1.0f)};
    }
    case Kind::kBox: {
      const glm::vec3 local = p - centre_;
      const glm::vec3 q = glm::abs(local) - extent_;
      if (glm::any(glm::greaterThan(q, glm::vec3(0.0f)))) {
        // Outside: from the nearest point of the box.
        const glm::vec3 outside = glm::max(q, glm::vec3(0.0f)) * glm::sign(local);
        const float length = glm::length(outside);
        return {length, outside / length};
      }
      // Inside: through the nearest face.
      const int axis = q.x > q.y ? (q.x > q.z ? 0 : 2) : (q.y > q.z ? 1 : 2);
      glm::vec3 normal(0.0f);
      normal[axis] = local[axis] < 0.0f ? -1.0f : 1.0f;
      return {q[axis], normal};
    }
    case Kind::kMesh:
      return mesh_->Nearest(p);
  }
  return {};
}

}  // namespace loom::animate
