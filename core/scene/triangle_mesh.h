#pragma once
// An indexed triangle mesh with the per-vertex attributes the renderers need.

#include <cstdint>
#include <glm/glm.hpp>
#include <limits>
#include <vector>

namespace loom {

struct TriangleMesh {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;
  std::vector<glm::vec2> uvs;
  // xyz: tangent along +u; w: handedness of the bitangent (+v).
  std::vector<glm::vec4> tangents;
  std::vector<uint32_t> indices;  // three per triangle

  size_t triangle_count() const { return indices.size() / 3; }
};

// An axis-aligned bounding box; empty until a point is added.
struct Bounds {
  glm::vec3 low{std::numeric_limits<float>::infinity()};
  glm::vec3 high{-std::numeric_limits<float>::infinity()};

  void Add(const glm::vec3& p) {
    low = glm::min(low, p);
    high = glm::max(high, p);
  }
  void Add(const std::vector<glm::vec3>& points) {
    for (const glm::vec3& p : points) Add(p);
  }
  bool empty() const { return !(high.x >= low.x); }
  float diagonal() const { return empty() ? 0.0f : glm::length(high - low); }
  glm::vec3 centre() const { return 0.5f * (low + high); }
};

}  // namespace loom
