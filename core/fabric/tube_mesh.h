#pragma once
// Yarn surfaces as swept tubes (DESIGN.md "Core engine" 1): the yarn's cross-section
// (SectionShape: a circle for knit yarns, a lens for woven ones) swept along a
// PeriodicYarn on rotation-minimising frames.
//
// Rotation-minimising frames (parallel transport, computed by double reflection,
// Wang et al. 2008) do not spin about the yarn, so the rings do not shear. Over one
// period the transported frame comes back rotated by the curve's holonomy angle; that
// angle is spread evenly along the yarn, so the frame at the end equals the frame at
// the start and the last vertex ring is the first ring translated by the period: the
// tile's mesh is exactly periodic.

#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <vector>

#include "core/fabric/periodic_yarn.h"
#include "core/scene/triangle_mesh.h"

namespace loom {

// The unit "up" axis of the cross-section at each point of the yarn (the section's
// thickness axis; its width axis is cross(tangent, up)). It starts as the fabric
// normal +z made perpendicular to the yarn, so a flat woven yarn lies flat, and the
// last one equals the first.
std::vector<glm::vec3> PeriodicFrameUp(const PeriodicYarn& yarn);

// Appends the tube around `yarn` to `mesh`, in tile space (positions scaled per axis by
// model_to_tile, normals by its inverse), and the yarn index of each new triangle to
// `triangle_yarn`. ring_vertices vertices around each ring (plus a seam duplicate for
// the texture coordinates).
//
// Per vertex: normal = the outward normal of the section; uv = (distance along the yarn
// in model units, angle around / 2π); tangent.xyz = the fibre direction: the yarn
// direction turned about the normal by the ply twist angle of the segment's yarn
// (twist_radians[yarn index]), as the surface fibres of a yarn twisted like a
// right-handed helix (positive angle) run; tangent.w = +1 or -1 so that
// w * cross(normal, tangent) points along +v.
void AppendTubeMesh(const PeriodicYarn& yarn, glm::vec3 model_to_tile, int ring_vertices,
                    std::span<const float> twist_radians, TriangleMesh& mesh, std::vector<uint32_t>& triangle_yarn);

}  // namespace loom
