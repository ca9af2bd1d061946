#pragma once
// Spec vectors and colours as glm values.

#include <glm/glm.hpp>

#include "loom/v1/fabric.pb.h"
#include "loom/v1/scene.pb.h"

namespace loom {

inline glm::vec3 ToGlm(const v1::Vec3& v) { return {v.x(), v.y(), v.z()}; }
inline glm::vec3 ToGlm(const v1::Rgb& c) { return {c.r(), c.g(), c.b()}; }

}  // namespace loom
