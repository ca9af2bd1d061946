#pragma once
// The direct term of acquisition's per-sample radiance (core/acquire/acquisition.h),
// shared with the reference renderer so that both shade yarn identically:
//   f_r(l, v) · cos θ_l · visible(l)   for unit irradiance E = 1,
// with one exact shadow ray through the repeated tile. The indirect term,
// ρ_d/π · E_ind(l), comes from core/acquire/indirect_light.h.

#include <cstdint>
#include <glm/glm.hpp>

#include "core/acquire/periodic_scene.h"
#include "core/acquire/surface_point.h"
#include "core/acquire/yarn_shading.h"

namespace loom {

// `point` is a front-facing yarn hit, l and v unit tile-space directions towards
// the light and the viewer. Sidedness is the triangle's: the hit faces v, so it is
// shaded even where the interpolated normal leans away from v (a silhouette); light
// behind the triangle is blocked even where the interpolated normal leans towards
// it, and light behind the interpolated normal gives no irradiance. Counts the
// shadow ray it casts in `rays`.
glm::vec3 DirectYarnRadiance(const PeriodicScene& scene, const SurfacePoint& point, const YarnBrdf& brdf, glm::vec3 l,
                             glm::vec3 v, uint64_t& rays);

}  // namespace loom
