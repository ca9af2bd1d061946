#include "core/acquire/yarn_radiance.h"

namespace loom {

glm::vec3 DirectYarnRadiance(const PeriodicScene& scene, const FabricTile& tile, const SurfacePoint& point,
                             const YarnBrdf& brdf, glm::vec3 l, glm::vec3 v, uint64_t& rays) {
  const float cosine = glm::dot(point.normal, l);
  const float facing = glm::dot(point.geometric_normal, l);
  if (cosine > 0.0f && facing > 0.0f) {
    ++rays;
    if (scene.Occluded(point.position + point.geometric_normal * kRayOffset, l)) return glm::vec3(0.0f);
    return brdf.Evaluate(point.normal, point.tangent, l, v) * cosine;
  }
  if (!(cosine < 0.0f && facing < 0.0f) || !brdf.transmits()) return glm::vec3(0.0f);
  // Through the yarn: the light's ray from the point's back meets this yarn's far
  // side first (a back face) and goes on from there unblocked.
  ++rays;
  if (const auto exit = scene.Intersect(point.position - point.geometric_normal * kRayOffset, l)) {
    const SurfacePoint far_side = MakeSurfacePoint(tile, *exit, l);
    if (far_side.front) return glm::vec3(0.0f);  // another yarn inside this one
    ++rays;
    if (scene.Occluded(far_side.position + far_side.geometric_normal * kRayOffset, l)) return glm::vec3(0.0f);
  }
  return brdf.Transmit(point.normal, point.tangent, l, v) * -cosine;
}

}  // namespace loom
