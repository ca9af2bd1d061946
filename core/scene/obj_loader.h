#pragma once
// Wavefront OBJ meshes for scenes, read with tinyobjloader. The text form is what
// travels: the server receives a mesh as uploaded bytes and never opens a client
// path (DESIGN.md "Security"), loom-lab reads a file and passes its text.
//
// The result is ready for PrepareMesh (core/scene/mesh_preparation.h): triangulated,
// one vertex per distinct (position, uv, normal) triple, normals empty when the
// file has none.

#include <string>
#include <string_view>

#include "core/scene/triangle_mesh.h"

namespace loom {

// `source` names the mesh in errors ("cloth.obj", "artifact 3fa2…"). Errors are
// Error(kInvalidArgument) naming the source and the problem: a parse error, no
// faces, no texture coordinates (a fabric is tiled through the UVs), a non-finite
// number, or more triangles than kMaxMeshTriangles.
TriangleMesh ParseObj(std::string_view text, const std::string& source);

}  // namespace loom
