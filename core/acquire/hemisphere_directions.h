#pragma once
// Directions over the upper hemisphere on a regular k×k grid: the view and light
// directions of acquisition (Daubert 2001 §4) and the per-view lookup table T(v)
// that the renderer interpolates bilinearly (§3).
//
// The map from the unit square to the hemisphere is Shirley and Chiu's concentric
// map (square → disk) followed by Lambert's azimuthal equal-area lift
// (disk → hemisphere: z = 1 − r², xy scaled by √(2 − r²)). Why this map:
// - Both steps preserve area, so every grid cell covers the same solid angle 2π/k²:
//   the directions are spread evenly and the fit weighs every direction alike.
//   (A hemi-octahedral map is as easy to invert but is not equal-area.)
// - The map is continuous and the square's border is exactly the horizon, each
//   square ring max(|2u−1|, |2v−1|) = const one elevation: a bilinear lookup
//   clamps at the border and never wraps.
// - Odd k puts a direction exactly at the zenith (the centre cell).
//
// Grid convention. Direction `index` = row·k + col sits at the centre of square
// cell (col, row): (u, v) = ((col + ½)/k, (row + ½)/k), u along +x (u = 1, v = ½ is
// the +x horizon) and v along +y. Continuous grid coordinates g = (u·k − ½, v·k − ½)
// put direction (col, row) at g = (col, row); a renderer interpolates between
// floor(g) and floor(g) + 1, each clamped to [0, k − 1].

#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

namespace loom {

// Shirley–Chiu concentric map, [0,1]² → unit disk, and its inverse. Shared with
// cosine-weighted sampling (Malley's method), which lifts the disk differently.
glm::vec2 ConcentricSquareToDisk(glm::vec2 square);
glm::vec2 ConcentricDiskToSquare(glm::vec2 disk);

// The equal-area map [0,1]² → unit directions with z ≥ 0, and its inverse. The
// inverse takes any direction: one below the horizon is first projected onto it
// (interpolated normals can put a view slightly below); the zero vector is the zenith.
glm::vec3 SquareToHemisphere(glm::vec2 square);
glm::vec2 HemisphereToSquare(glm::vec3 direction);

// The side k of a grid of `count` = k² directions; throws Error(kInvalidArgument)
// unless count is a non-zero perfect square (the validator guarantees it for specs).
uint32_t HemisphereGridSide(uint32_t count);

// All k² unit directions in index order (row-major, see above).
std::vector<glm::vec3> HemisphereGridDirections(uint32_t count);

// `directions` mirrored through the surface (z negated): a grid below the cloth, or
// one below brought back above it.
std::vector<glm::vec3> MirroredThroughTheSurface(std::vector<glm::vec3> directions);

// Continuous grid coordinates of a direction on a k×k grid, in [−½, k − ½]².
glm::vec2 HemisphereGridCoordinates(glm::vec3 direction, uint32_t side);

}  // namespace loom
