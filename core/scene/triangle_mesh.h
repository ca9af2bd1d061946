#pragma once
// An indexed triangle mesh with the per-vertex attributes the renderers need.

#include <cstdint>
#include <glm/glm.hpp>
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

}  // namespace loom
