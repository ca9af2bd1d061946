#include "core/acquire/surface_point.h"

#include <cmath>

namespace loom {

SurfacePoint MakeSurfacePoint(const FabricTile& tile, const RayHit& hit, glm::vec3 direction) {
  const TriangleMesh& mesh = tile.mesh;
  const uint32_t* corner = &mesh.indices[3 * size_t{hit.triangle}];
  const float w1 = hit.barycentric.x, w2 = hit.barycentric.y, w0 = 1.0f - w1 - w2;
  auto interpolate = [&](const auto& attribute) {
    return w0 * glm::vec3(attribute[corner[0]]) + w1 * glm::vec3(attribute[corner[1]]) +
           w2 * glm::vec3(attribute[corner[2]]);
  };

  SurfacePoint point;
  point.position = hit.position;
  point.material = tile.triangle_material[hit.triangle];
  const glm::vec3 p0 = mesh.positions[corner[0]];
  const glm::vec3 face = glm::cross(mesh.positions[corner[1]] - p0, mesh.positions[corner[2]] - p0);
  const glm::vec3 geometric = SafeNormalize(face, -direction);
  point.normal = SafeNormalize(interpolate(mesh.normals), geometric);
  point.geometric_normal = glm::dot(geometric, point.normal) < 0.0f ? -geometric : geometric;
  point.front = glm::dot(point.geometric_normal, direction) < 0.0f;
  point.tangent = interpolate(mesh.tangents);
  return point;
}

}  // namespace loom
