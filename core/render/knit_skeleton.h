#pragma once
// A knit cloth's yarns placed on its scene mesh (the lumislice paper §5.2: the knitwear
// skeleton on the surface, its key points mapped by s(u, v)): what the lumislice
// renderer cuts into slices. Each course of the fabric's tile (core/fabric/knit_tile.h)
// is repeated across the mesh's uv square × repeat, one chain per course and tile row,
// and a tile-space point (x, y, z) goes to world space by the triangle whose tile-space
// image (uv·repeat) holds (x, y): P(b) + z·s_u·n(b), b its barycentric coordinates, P
// and n the triangle's interpolated position and unit normal, s_u its world length per
// tile unit along u (the reference's shell mapping, core/render/reference_renderer.h).
// A chain is cut where it leaves the mesh. Along a chain a normal is transported and
// the section turns at the yarn's twist rate, as in the tile's yarn volume.

#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "core/scene/triangle_mesh.h"
#include "loom/v1/fabric.pb.h"

namespace loom {

struct SkeletonChain {
  std::vector<glm::vec3> points;   // world space
  std::vector<glm::vec3> normals;  // unit, ⊥ the chain, transported along it
  std::vector<float> turn;         // the section's turn (radians) at each point
  std::vector<float> radius;       // the yarn's radius (world units) at each point
  std::vector<uint32_t> segment_yarn;  // FabricSpec.yarns index of segment [i, i + 1]
};

struct KnitSkeleton {
  std::vector<SkeletonChain> chains;
  size_t segment_count() const;
};

// `fabric` a knit with WithDefaults applied; `mesh` in world space with uvs; `repeat`
// tiles across its uv square.
KnitSkeleton PlaceKnitSkeleton(const v1::FabricSpec& fabric, const TriangleMesh& mesh, glm::vec2 repeat);

}  // namespace loom
