#pragma once
// Loom's built-in meshes (SceneSpec BuiltinShape), each with normals, UVs in
// [0,1]² and tangents along +u, so a fabric can be tiled over them.

#include "core/scene/triangle_mesh.h"

namespace loom {

// Unit square in the xy plane centred at the origin, normal +z, uv = xy + 0.5.
TriangleMesh MakePlane(int segments);
// Unit sphere; u = longitude / 2π, v = latitude from the south pole.
TriangleMesh MakeSphere(int segments);
// Unit-radius, unit-height open cylinder around z; u around, v up.
TriangleMesh MakeCylinder(int segments);

}  // namespace loom
