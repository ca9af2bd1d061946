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
// A 2 x 2 cloth draped over a sphere of radius 0.5 at the origin like a
// tablecloth: it follows the sphere's upper half, then hangs from the equator in
// folds that deepen with the hanging length. uv = the flat cloth's xy / 2 + 0.5,
// so arc length along the cloth matches uv distance (the fabric is not stretched
// radially). Normals and tangents come from PrepareMesh.
TriangleMesh MakeDrape(int segments);

}  // namespace loom
