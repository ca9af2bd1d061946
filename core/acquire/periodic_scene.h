#pragma once
// A fabric tile's triangles repeated over the plane with period 1 in x and y, for
// ray casting with Embree: Daubert's "paste together multiple copies of the
// geometry" (2001 §4), so that holes show what lies below and beside the tile.
//
// The repetition is an Embree instance grid over the tile's mesh, sized so that a
// ray starting above the central tile [0,1)² is covered for `reach` tiles of
// horizontal travel (plus the mesh's overhang past the tile edges). A ray that
// stays inside the geometry's z slab for longer (a grazing inter-reflection ray) is
// continued exactly: periodicity lets the walk move the ray's current point back
// into the central tile and cast again. So every query answers for the infinitely
// repeated tile; the grid size only decides how many Embree calls a ray needs.
// Acquisition chooses `reach` from its most grazing view and light direction, so
// its primary and shadow rays need one call each.

#include <cstdint>
#include <glm/glm.hpp>
#include <memory>
#include <optional>

#include "core/scene/triangle_mesh.h"

namespace loom {

struct RayHit {
  uint32_t triangle = 0;    // index into the tile mesh
  glm::vec2 barycentric{};  // Embree's (u, v): weights of the triangle's 2nd and 3rd vertex
  // The hit point in a copy near the central tile: the ray's origin was moved into
  // [0,1)², so this is the true hit point minus a whole-tile offset.
  glm::vec3 position{};
};

class PeriodicScene {
 public:
  // Rays that stay closer than `reach` tiles (clamped to [1, kMaxReach]) to the
  // central tile need one Embree call. Throws Error(kInternal) if Embree fails.
  PeriodicScene(const TriangleMesh& mesh, float reach);
  ~PeriodicScene();
  PeriodicScene(const PeriodicScene&) = delete;
  PeriodicScene& operator=(const PeriodicScene&) = delete;

  // The first hit along origin + t·direction, t > 0, in the repeated tile; rays
  // end where they leave the geometry's z slab. `direction` must be unit.
  std::optional<RayHit> Intersect(glm::vec3 origin, glm::vec3 direction) const;
  // Whether anything lies along origin + t·direction, t > 0.
  bool Occluded(glm::vec3 origin, glm::vec3 direction) const;

  // Copies of the tile along x and y in the instance grid (for reports).
  glm::ivec2 grid_size() const;

  // Embree walks at most this many tiles of horizontal travel in one call; beyond
  // it, continuing costs one call per `kMaxReach` tiles instead of ever more memory.
  static constexpr float kMaxReach = 16.0f;
  // A grazing ray continued this many times without a hit or leaving the slab
  // counts as escaping (it has crossed at least that many tiles nearly flat).
  static constexpr int kMaxContinuations = 64;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace loom
