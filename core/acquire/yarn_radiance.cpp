#include "core/acquire/yarn_radiance.h"

namespace loom {

glm::vec3 DirectYarnRadiance(const PeriodicScene& scene, const SurfacePoint& point, const YarnBrdf& brdf, glm::vec3 l,
                             glm::vec3 v, uint64_t& rays) {
  const float cosine = glm::dot(point.normal, l);
  if (!(cosine > 0.0f && glm::dot(point.geometric_normal, l) > 0.0f)) return glm::vec3(0.0f);
  ++rays;
  const glm::vec3 shadow_origin = point.position + point.geometric_normal * kRayOffset;
  if (scene.Occluded(shadow_origin, l)) return glm::vec3(0.0f);
  return brdf.Evaluate(point.normal, point.tangent, l, v) * cosine;
}

}  // namespace loom
