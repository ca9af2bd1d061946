#pragma once
// Which points of a knit cloth may touch which of its own triangles (the
// lumislice paper §4.1.2: a point feels the thickness field of every
// non-adjacent triangle within T of it). An Embree BVH over the cloth's
// triangles answers one point query per point, radius reach + skin; the pairs
// found stay a superset of those within `reach` while no point has moved more
// than skin / 2 since, so they are searched again only then. A triangle whose
// cell has a corner within `exclusion` grid rings of the point is left out: that
// is the point's own neighbourhood, which its springs and angle forces hold
// (docs/animation.md "Self-contact").

#include <cstdint>
#include <glm/glm.hpp>
#include <memory>
#include <vector>

#include "core/animate/knit_cloth.h"

namespace loom::animate {

struct PointTriangle {
  uint32_t point = 0, triangle = 0;
};

class SelfContactPairs {
 public:
  // reach > 0, skin > 0, exclusion ≥ 0. `threads` as ParallelFor's (0: every core).
  SelfContactPairs(const KnitCloth& cloth, float reach, float skin, int exclusion, unsigned threads = 0);
  ~SelfContactPairs();
  SelfContactPairs(SelfContactPairs&&) noexcept;
  SelfContactPairs& operator=(SelfContactPairs&&) noexcept;

  // Makes pairs() hold every pair within `reach` at positions x (the cloth's
  // points): searches again if a point has moved more than skin / 2 since the
  // last search.
  void Update(const std::vector<glm::vec3>& x);

  // Sorted by point, then triangle.
  const std::vector<PointTriangle>& pairs() const { return pairs_; }
  const std::vector<glm::uvec3>& triangles() const { return triangles_; }
  float reach() const { return reach_; }
  long searches() const { return searches_; }

 private:
  void Search(const std::vector<glm::vec3>& x);

  struct Bvh;  // the Embree device, scene and vertex buffer
  std::unique_ptr<Bvh> bvh_;
  KnitCloth cloth_;  // its topology; positions are the caller's
  std::vector<glm::uvec3> triangles_;
  float reach_, skin_;
  int exclusion_;
  unsigned threads_;
  std::vector<glm::vec3> searched_at_;  // the positions of the last search
  std::vector<PointTriangle> pairs_;
  long searches_ = 0;
};

}  // namespace loom::animate
