#include "core/fabric/periodic_yarn.h"

#include <algorithm>
#include <cmath>

namespace loom {

SectionPoint SectionBoundary(SectionShape shape, glm::vec2 half_extent, float angle) {
  const float a = half_extent.x, b = half_extent.y;
  const float c = std::cos(angle), s = std::sin(angle);
  if (shape == SectionShape::kEllipse) {
    // The gradient of (u/a)² + (v/b)² is the outward normal.
    return {{a * c, b * s}, glm::normalize(glm::vec2(c / a, s / b))};
  }
  // Lens: u = a cos, |v| = b (1 - cos²) = b sin²; gradient of |v| - b (1 - u²/a²).
  // sin(π) is not exactly 0 in float: an edge is where |sin| is below rounding.
  const bool edge = std::abs(s) < 1e-6f;
  const glm::vec2 normal = edge ? glm::vec2(c, 0.0f) : glm::vec2(2.0f * b * c / a, s > 0 ? 1.0f : -1.0f);
  return {{a * c, b * s * std::abs(s)}, glm::normalize(normal)};
}

std::vector<YarnCurve> TileCurves(const TileYarns& tile_yarns) {
  std::vector<YarnCurve> curves;
  for (const PeriodicYarn& yarn : tile_yarns.yarns) {
    const size_t segments = yarn.segment_yarn.size();
    size_t begin = 0;
    while (begin < segments) {
      size_t end = begin + 1;
      while (end < segments && yarn.segment_yarn[end] == yarn.segment_yarn[begin]) ++end;
      YarnCurve curve;
      curve.yarn_index = yarn.segment_yarn[begin];
      for (size_t i = begin; i <= end; ++i) {
        curve.points.push_back(yarn.points[i] * tile_yarns.model_to_tile);
        curve.radius = std::max(curve.radius, yarn.section[i].y * tile_yarns.model_to_tile.x);
      }
      // A yarn spans one period and continues in its periodic copy: never a closed loop.
      curve.closed = false;
      curves.push_back(std::move(curve));
      begin = end;
    }
  }
  return curves;
}

}  // namespace loom
