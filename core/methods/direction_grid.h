#pragma once
// A direction's place on a k×k hemisphere grid of stored directions
// (core/acquire/hemisphere_directions.h) and bilinear interpolation between the four
// stored directions around it: the C++ twin of fabric_surface.glsl's LocateOnGrid
// and of the GPU's filtering inside a block, for the methods that store tables over
// the grids (their Evaluate functions, which tests compare with the shaders).

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "core/acquire/hemisphere_directions.h"

namespace loom {

// k of the k×k grid that holds `count` stored directions.
inline uint32_t GridSide(size_t count) { return HemisphereGridSide(static_cast<uint32_t>(count)); }

struct GridPoint {
  glm::ivec2 lower, upper;  // stored (col, row) corners, clamped to the grid
  glm::vec2 weight;         // towards `upper`
  float beyond_ring;        // how far past the outermost stored ring, [0, 1]
};

inline GridPoint LocateOnGrid(glm::vec3 direction, uint32_t side) {
  const float k = static_cast<float>(side);
  const glm::vec2 unclamped = HemisphereGridCoordinates(direction, side);
  const glm::vec2 grid = glm::clamp(unclamped, glm::vec2(0.0f), glm::vec2(k - 1.0f));
  const glm::vec2 beyond = glm::max(-unclamped, unclamped - (k - 1.0f));
  GridPoint point;
  point.lower = glm::ivec2(glm::floor(grid));
  point.upper = glm::min(point.lower + 1, glm::ivec2(static_cast<int>(side) - 1));
  point.weight = grid - glm::vec2(point.lower);
  point.beyond_ring = std::clamp(2.0f * std::max(beyond.x, beyond.y), 0.0f, 1.0f);
  return point;
}

// Bilinear over the four stored directions around `point`; value(index) at one of
// them, index = row·side + col.
template <typename T, typename Value>
T Bilinear(const GridPoint& point, uint32_t side, const Value& value) {
  const auto at = [&](int col, int row) { return value(static_cast<size_t>(row) * side + static_cast<size_t>(col)); };
  const T bottom = glm::mix(at(point.lower.x, point.lower.y), at(point.upper.x, point.lower.y), point.weight.x);
  const T top = glm::mix(at(point.lower.x, point.upper.y), at(point.upper.x, point.upper.y), point.weight.x);
  return glm::mix(bottom, top, point.weight.y);
}

// Where a ray from `direction` (unit, tile frame) meets the fabric whose macro
// surface it crosses at tile coordinate `surface`: on the plane of the texels'
// sampling height for that direction, the stored views' heights
// (RadianceSamples::view_heights) interpolated like the view atlas; the slope is
// capped near grazing, where the plane is seen edge-on. fabric_surface.glsl's
// FabricTile is its twin.
inline glm::vec2 FabricTileAt(glm::vec2 surface, glm::vec3 direction, const std::vector<float>& view_heights) {
  const uint32_t side = GridSide(view_heights.size());
  const float height =
      Bilinear<float>(LocateOnGrid(direction, side), side, [&](size_t view) { return view_heights[view]; });
  return surface + glm::vec2(direction) / std::max(direction.z, 0.1f) * height;
}

// A light's weight: 0 below the horizon, fading from 1 at the outermost stored ring
// to 0 at the horizon (radiance holds cos θ_l, which goes to 0 there).
inline float LightWeight(glm::vec3 light, const GridPoint& point) {
  return light.z > 0.0f ? 1.0f - point.beyond_ring : 0.0f;
}

}  // namespace loom
