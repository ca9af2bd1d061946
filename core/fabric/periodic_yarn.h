#pragma once
// The yarns of one fabric tile as the knit and woven models build them, before they
// become YarnCurves and a mesh: each yarn spans exactly one period of the tile (a knit
// course across the tile in x, a woven thread across it in x or y), so its periodic
// copies join it end to end and the tile repeats seamlessly.
//
// The models work in "model units": lengths in loop widths (knit) or yarn pitches
// (woven), the units of YarnSpec.radius, with z up. model_to_tile scales model space
// per axis onto the tile's [0,1)² (and z by the same factor as x). Non-interpenetration
// holds in model space, where the yarns are round (knit) or lens-shaped (woven) tubes;
// an affine map keeps disjoint solids disjoint, so it holds in tile space too.

#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "core/fabric/fabric_tile.h"

namespace loom {

// A yarn's cross-section, spanned by a half-width a (along the fabric plane) and a
// half-thickness b (across it).
enum class SectionShape {
  kEllipse,  // (u/a)² + (v/b)² = 1; a circle when a == b (knit yarns)
  kLens,     // lenticular |v| = b (1 - (u/a)²): a flattened woven yarn whose thickness
             // falls linearly to sharp edges (see woven_tile.h for why not an ellipse)
};

struct SectionPoint {
  glm::vec2 offset{0.0f};  // (u, v) from the centre
  glm::vec2 normal{0.0f};  // unit outward normal in the section plane
};

// The boundary point at parameter angle ∈ [0, 2π): u = a cos(angle), v >= 0 for
// angle ∈ [0, π]. At a lens's sharp edges the normal is the average of both sides.
SectionPoint SectionBoundary(SectionShape shape, glm::vec2 half_extent, float angle);

struct PeriodicYarn {
  // Centre line samples; points.back() is points.front() + period exactly.
  std::vector<glm::vec3> points;
  // Unit direction of the yarn at each point.
  std::vector<glm::vec3> tangents;
  // The translation after which the yarn repeats: (wales, 0, 0) for a knit course,
  // (n, 0, 0) or (0, n, 0) for a weft or warp thread of an n-yarn weave repeat.
  glm::vec3 period{0.0f};
  // Cross-section per point: x = half-width a, y = half-thickness b.
  std::vector<glm::vec2> section;
  SectionShape shape = SectionShape::kEllipse;
  // FabricSpec.yarns index of each segment [points[i], points[i + 1]].
  std::vector<uint32_t> segment_yarn;
};

struct TileYarns {
  std::vector<PeriodicYarn> yarns;
  glm::vec3 model_to_tile{1.0f};
};

// The yarn centre curves in tile space, one YarnCurve per run of segments with the same
// yarn index (a knit course changes yarn where its colour pattern does). Each curve's
// radius is the largest half-thickness along it, in units of the tile's x axis.
std::vector<YarnCurve> TileCurves(const TileYarns& tile_yarns);

}  // namespace loom
