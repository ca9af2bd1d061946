#pragma once
// The direct term of acquisition's per-sample radiance (core/acquire/acquisition.h),
// shared with the reference renderer so that both shade yarn identically:
//   f_r(l, v) · cos θ_l · visible(l)      l in front of the surface, or
//   f_t(l, v) · |cos θ_l| · through(l)    l behind it, for a yarn that transmits,
// for unit irradiance E = 1, with exact shadow rays through the repeated tile.
// through(l): the light's ray from the point's back leaves the yarn through its far
// side before it meets anything, and nothing blocks it from there (two rays). The indirect term,
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
// reflects only where both the triangle and the interpolated normal face l, and
// transmits only where neither does. `tile` is the scene's geometry. Counts the rays
// it casts in `rays`.
glm::vec3 DirectYarnRadiance(const PeriodicScene& scene, const FabricTile& tile, const SurfacePoint& point,
                             const YarnBrdf& brdf, glm::vec3 l, glm::vec3 v, uint64_t& rays);

}  // namespace loom
