#pragma once
// Test support: how close the yarns of a tile come to touching. Every yarn and its
// copies in the 3×3 neighbourhood of tiles are compared by their densely sampled
// centre lines in model space (where the yarns are round or elliptical tubes).

#include <glm/glm.hpp>

#include "core/fabric/periodic_yarn.h"

namespace loom {

struct Clearance {
  // The smallest distance between two centre points divided by the distance the two
  // cross-sections need along that line (each section's extent towards the other:
  // 2r for two round yarns of radius r). Below 1 the tubes overlap there.
  float ratio = 0.0f;
  glm::vec3 where{0.0f};  // midpoint of the closest pair, model space
  size_t yarn_a = 0, yarn_b = 0;
};

// Pairs on the same yarn (or its periodic continuation) count only when they are
// more than π·r apart along the yarn, the shortest arc that can bend back to touch.
// Exact for round yarns; for flat elliptical ones the line of centres is not the best
// separating direction, and SurfaceClearance is the measure to use.
Clearance MeasureClearance(const TileYarns& tile);

// How far outside every other tube the surface of each tube stays: over the surface
// points (ring_vertices around each centre sample), the smallest factor by which the
// cross-section of another tube, in whose normal plane the point lies, would have to
// grow to reach it (for an ellipse sqrt((u/a)² + (v/b)²)). 1 where the surfaces touch,
// below 1 inside. Same-yarn pairs as in MeasureClearance.
Clearance SurfaceClearance(const TileYarns& tile, int ring_vertices);

// The smallest radius of curvature along the yarns divided by the local yarn radius
// (the larger semi-axis): below 1 a tube folds over itself.
float MinCurvatureRatio(const TileYarns& tile);

}  // namespace loom
