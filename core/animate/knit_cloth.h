#pragma once
// A knit cloth as the lumislice paper animates it (§4.1.1): a mass-spring mesh
// whose mass points are the knit's loops (u, v), `across` loops in a course and
// `along` courses. Neighbours in a course and in a wale are joined by springs
// whose rest lengths are the loop spacings; bending acts on three loops in a
// row, shearing on the corners of each cell. This is the mesh's initial state
// and topology; the motion is core/animate/knit_simulation.h's.

#include <glm/glm.hpp>
#include <vector>

namespace loom::animate {

struct KnitCloth {
  int across = 0;                    // loops in a course (u)
  int along = 0;                     // courses (v)
  float course_spacing = 1.0f;       // rest length between neighbours in a course
  float wale_spacing = 1.0f;         // rest length between neighbours in a wale
  std::vector<glm::vec3> positions;  // point (i, j) at j · across + i

  size_t Index(int i, int j) const { return static_cast<size_t>(j) * across + i; }
  size_t size() const { return positions.size(); }

  // The mesh's triangles, two per cell, split along the diagonal its shearing
  // corners share: cell (i, j) gives (i, j)(i+1, j)(i, j+1), then
  // (i+1, j)(i+1, j+1)(i, j+1). Triangle t belongs to cell t / 2, cells in
  // row-major order.
  std::vector<glm::uvec3> Triangles() const;
  // Whether triangle t's cell has a corner within `rings` loops of point p along
  // the grid (Chebyshev distance): p's own neighbourhood, not a contact.
  bool Adjacent(size_t point, size_t triangle, int rings) const;
};

// A flat cloth at rest: loop (i, j) at origin + i·course_spacing·course +
// j·wale_spacing·wale (course and wale unit vectors). Error(kInvalidArgument)
// for fewer than 2 loops either way, a spacing ≤ 0 or parallel axes.
KnitCloth FlatKnitCloth(int across, int along, float course_spacing, float wale_spacing, glm::vec3 origin,
                        glm::vec3 course, glm::vec3 wale);

}  // namespace loom::animate
