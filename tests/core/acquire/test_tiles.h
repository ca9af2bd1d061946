#pragma once
// Small hand-built fabric tiles for the acquisition tests and benchmark (they do
// not depend on BuildFabricTile): a flat patch, straight tubes ("yarns") along x
// or y, and unions of them.

#include <cstdint>
#include <vector>

#include "core/fabric/fabric_tile.h"

namespace loom::testing {

// A white-ish Lambertian material (no fibre lobe) unless told otherwise.
YarnMaterial Lambertian(float albedo);

// The square [0,1]² at height z, normal +z, tangent +x: two triangles.
FabricTile FlatPatch(float z, const YarnMaterial& material);

// A straight tube of `radius` whose axis runs along x (at y = offset, z = height)
// or along y (at x = offset), across the whole tile, so that the repeated tile
// makes an infinite cylinder. Normals outwards, tangents along the axis;
// `around` × `along` quads.
enum class Axis { kX, kY };
struct Tube {
  Axis axis = Axis::kX;
  float offset = 0.5f;
  float height = 0.5f;
  float radius = 0.1f;
};
FabricTile Tubes(const std::vector<Tube>& tubes, const YarnMaterial& material, uint32_t around = 32,
                 uint32_t along = 8);

// A zig-zag surface across y (a ridge at y = ½, valleys at y = 0 and 1, 45° slopes,
// height ½): repeated, a row of V-grooves with a 90° opening along x. `segments`
// quads down each slope.
FabricTile VGrooves(const YarnMaterial& material, uint32_t segments);

// The union of two tiles' geometry and materials; z range of both.
FabricTile Merge(const FabricTile& a, const FabricTile& b);

}  // namespace loom::testing
