#pragma once
// Spec vectors and colours as glm values, and back.

#include <glm/glm.hpp>

#include "loom/v1/fabric.pb.h"
#include "loom/v1/scene.pb.h"

namespace loom {

inline glm::vec3 ToGlm(const v1::Vec3& v) { return {v.x(), v.y(), v.z()}; }
inline glm::vec3 ToGlm(const v1::Rgb& c) { return {c.r(), c.g(), c.b()}; }

inline v1::Vec3 ToVec3(glm::vec3 g) {
  v1::Vec3 v;
  v.set_x(g.x);
  v.set_y(g.y);
  v.set_z(g.z);
  return v;
}

}  // namespace loom
