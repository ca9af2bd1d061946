#pragma once
// Makes a mesh safe to render: drops degenerate triangles (counted, not fatal),
// fills in missing normals (area-weighted) and computes tangents along +u from the
// UV parameterisation. Triangles whose UVs have zero area (the fabric is squashed
// to a line there) keep a tangent perpendicular to the normal, never NaN.

#include <cstddef>

#include "core/scene/triangle_mesh.h"

namespace loom {

struct MeshPreparationReport {
  size_t dropped_degenerate_triangles = 0;  // zero area in 3-D
  size_t zero_area_uv_triangles = 0;        // kept; their tangents are a fallback
  size_t fallback_tangents = 0;             // vertices whose UV tangent was undefined
};

// `source` names the mesh in errors and warnings. Throws Error(kInvalidArgument)
// when no triangle is left. A mesh without UVs (a plain diffuse object's) gets
// (0, 0) everywhere and tangents perpendicular to its normals, without a warning.
MeshPreparationReport PrepareMesh(TriangleMesh& mesh, const char* source);

}  // namespace loom
