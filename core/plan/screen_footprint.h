#pragma once
// How large a fabric's tile appears on screen: the input of "model no more than a
// scene needs" (DESIGN.md "Measurement protocol"). A fitted level finer than a
// pixel is never shown (the svbrdf renderer picks the level whose texel matches the
// pixel footprint's area), so the largest on-screen tile bounds the spatial
// resolution a scene can use.

#include <vector>

#include "core/scene/scene_geometry.h"
#include "loom/v1/scene.pb.h"

namespace loom {

struct TileFootprint {
  // Side of one tile in pixels (the square root of its projected area), the
  // largest and smallest over the visible triangles; 0 when none is visible.
  double largest_pixels = 0.0;
  double smallest_pixels = 0.0;
  int visible_triangles = 0;
};

// Per triangle of `mesh` (an object of `scene` that carries a fabric; `scene` with
// defaults applied): its projected pixel area over the tiles it holds (UV area ×
// repeat_u × repeat_v). Triangles behind the near plane, outside the frame or with
// zero UV area are skipped; both faces count (cloth is two-sided). The figure is
// the triangle's average, so a large triangle seen in steep perspective reports
// less than its nearest corner shows.
TileFootprint MeasureTileFootprint(const v1::SceneSpec& scene, const SceneMesh& mesh);

}  // namespace loom
