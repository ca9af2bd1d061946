#pragma once
// The shading geometry of the yarn surface at a ray hit, from the tile mesh's
// per-vertex attributes. Yarn surfaces are closed and their vertex normals point
// outwards; the mesh's winding order is not relied on. A ray that reaches the
// inside of a surface (yarns that touch, an open test patch seen from below) sees
// an unlit back face: opaque and black.

#include <cstdint>
#include <glm/glm.hpp>

#include "core/acquire/periodic_scene.h"
#include "core/fabric/fabric_tile.h"
#include "core/util/vector_math.h"

namespace loom {

// How far rays that leave a surface (shadow and gather rays) start off it, along
// its normal, in tile units: far above float rounding at tile coordinates (~1e-7)
// and far below yarn radii (~1e-1) and triangle sizes (~1e-2).
inline constexpr float kRayOffset = 1e-4f;

struct SurfacePoint {
  glm::vec3 position{};          // RayHit::position
  glm::vec3 normal{};            // unit shading normal (interpolated vertex normals)
  glm::vec3 geometric_normal{};  // unit triangle normal, on the shading normal's side
  glm::vec3 tangent{};           // interpolated yarn direction, not normalised (YarnBrdf
                                 // makes it a unit vector in the surface)
  uint32_t material = 0;         // index into FabricTile::materials
  bool front = true;             // the ray came from outside the surface
};

// `direction` is the ray's unit direction. Degenerate attributes fall back rather
// than produce NaN: a zero interpolated normal becomes the triangle normal, and
// both vanishing make the surface face the ray.
SurfacePoint MakeSurfacePoint(const FabricTile& tile, const RayHit& hit, glm::vec3 direction);

}  // namespace loom
