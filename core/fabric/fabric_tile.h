#pragma once
// One exactly periodic tile of a fabric's micro-geometry (DESIGN.md "Core engine" 1):
// the yarn centre curves and the triangle mesh of the yarn surfaces, in tile space
// x, y ∈ [0, 1) (one tile; the tile repeats with period 1 in x and y), z up, the
// fabric's top face towards +z. Built from a FabricSpec by BuildFabricTile.

#include <cstdint>
#include <glm/glm.hpp>
#include <memory>
#include <vector>

#include "core/scene/triangle_mesh.h"
#include "loom/v1/fabric.pb.h"

namespace loom {

class YarnVolume;

// A yarn's centre line: a closed or open polyline densely sampled from cardinal
// splines through key points. Points may leave [0,1)²: a yarn crossing the tile's
// edge continues into the neighbouring tile, and its periodic copy enters from the
// other side.
struct YarnCurve {
  std::vector<glm::vec3> points;
  float radius = 0.0f;       // tile units
  uint32_t yarn_index = 0;   // into FabricSpec.yarns / FabricTile.materials
  bool closed = false;
};

// The yarn material (docs/yarn_shading.md), RGB: Lambertian diffuse plus a
// Kajiya-Kay fibre lobe about the yarn tangent, or the fibre-microflake model.
enum class YarnShadingModel { kKajiyaKay, kMicroflake };
struct YarnMaterial {
  YarnShadingModel model = YarnShadingModel::kKajiyaKay;
  glm::vec3 diffuse_albedo{0.5f};
  glm::vec3 specular_albedo{0.04f};
  float specular_exponent = 32.0f;  // Kajiya-Kay: from YarnSpec.roughness
  float roughness = 0.5f;           // microflake: α
  float height_scale = 1.0f;        // microflake: β
  float lambert_blend = 1.0f;       // microflake: w
  float diffuse_transmission = 0.0f;  // microflake: t
};

struct FabricTile {
  std::vector<YarnCurve> curves;
  // The yarn surfaces. mesh.tangents[v].xyz is the unit yarn direction at vertex v
  // (the fibre direction the Kajiya-Kay lobe is about).
  TriangleMesh mesh;
  // Per triangle: index into `materials`.
  std::vector<uint32_t> triangle_material;
  std::vector<YarnMaterial> materials;
  // z range of the geometry (the tile's bounding slab; the volume's, when there is one).
  float z_min = 0.0f;
  float z_max = 0.0f;
  // A knit whose yarns have plies or fuzz: the yarns as a volume of fibres
  // (core/fabric/yarn_volume.h), which is what rays meet; the mesh stays the tubes
  // the volume's yarns are centred on (their surfaces give texel normals). Null: the
  // yarns are the mesh's opaque tubes.
  std::shared_ptr<const YarnVolume> volume;
};

// Throws Error(kInvalidArgument) if the spec does not validate.
FabricTile BuildFabricTile(const v1::FabricSpec& spec);

}  // namespace loom
