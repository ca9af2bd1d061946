#pragma once
// Wavefront OBJ export of a mesh, so any other renderer can check Loom's geometry
// (`loom-lab geometry --obj`).

#include <filesystem>

#include "core/scene/triangle_mesh.h"

namespace loom {

// Writes `mesh` repeated tiles_x × tiles_y times, copy (i, j) moved by (i, j, 0): a
// fabric tile has period 1 in x and y, so the copies join into one patch. Positions
// are written per copy; texture coordinates and normals, the same in every copy, once
// (OBJ faces index them separately: "f v/vt/vn", 1-based). Meshes without uvs or
// normals get faces without them. Written atomically (WriteFileAtomic).
void WriteObj(const TriangleMesh& mesh, const std::filesystem::path& path, int tiles_x = 1, int tiles_y = 1);

}  // namespace loom
