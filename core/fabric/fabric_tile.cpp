#include "core/fabric/fabric_tile.h"

#include <algorithm>
#include <cmath>
#include <mutex>
#include <numbers>
#include <set>
#include <string>
#include <tuple>

#include <spdlog/spdlog.h>

#include "core/fabric/knit_tile.h"
#include "core/fabric/tube_mesh.h"
#include "core/fabric/woven_tile.h"
#include "core/fabric/yarn_material.h"
#include "core/fabric/yarn_volume.h"
#include "core/spec/defaults.h"
#include "core/spec/validate.h"
#include "core/util/error.h"

namespace loom {
namespace {

// Mesh density: 8 spline samples between knit key points (56 per loop) and 10 per
// woven crossing follow the yarn's bends (a knit loop bends about as tightly as the
// yarn is thick); 16 vertices round a ring, an even count so that a lens has vertices
// on both of its sharp edges. The largest tiles the validator accepts (32 × 32 loops,
// a 32-thread weave repeat) come to 1.8 and 0.7 million triangles.
constexpr int kKnitSamplesPerSegment = 8;
constexpr int kWovenSamplesPerCrossing = 10;
constexpr int kRingVertices = 16;

// Plies and fuzz are part of the schema (DESIGN.md) and of the cache key; knit yarns
// with them are a volume of fibres, but woven yarns stay one round tube, their twist only
// tilting the fibre highlight. Said once per yarn (name, plies, fuzz) and process,
// so a sweep that builds the same tile for every reference row logs it once.
void WarnOfUnmodelledYarnFields(const v1::FabricSpec& fabric) {
  if (fabric.has_knit()) return;
  static std::mutex mutex;
  static std::set<std::tuple<std::string, uint32_t, float>> warned;
  for (const v1::YarnSpec& yarn : fabric.yarns()) {
    if (yarn.plies() <= 1 && yarn.fuzz() <= 0.0f) continue;
    const std::lock_guard lock(mutex);
    if (!warned.emplace(yarn.name(), yarn.plies(), yarn.fuzz()).second) continue;
    spdlog::warn("yarn '{}': plies ({}) and fuzz ({}) of woven yarns are not modelled yet; the yarn is one round "
                 "tube whose twist tilts its fibre highlight",
                 yarn.name(), yarn.plies(), yarn.fuzz());
  }
}

}  // namespace

FabricTile BuildFabricTile(const v1::FabricSpec& spec) {
  ThrowIfAny(Validate(spec));
  const v1::FabricSpec fabric = WithDefaults(spec);
  WarnOfUnmodelledYarnFields(fabric);
  const TileYarns yarns = fabric.has_knit() ? BuildKnitYarns(fabric, kKnitSamplesPerSegment)
                                            : BuildWovenYarns(fabric, kWovenSamplesPerCrossing);

  FabricTile tile;
  tile.curves = TileCurves(yarns);
  std::vector<float> twist_radians;
  for (const v1::YarnSpec& yarn : fabric.yarns()) {
    tile.materials.push_back(MakeYarnMaterial(yarn));
    twist_radians.push_back(yarn.twist_degrees() * std::numbers::pi_v<float> / 180.0f);
  }
  for (const PeriodicYarn& yarn : yarns.yarns) {
    AppendTubeMesh(yarn, yarns.model_to_tile, kRingVertices, twist_radians, tile.mesh, tile.triangle_material);
  }
  const auto [low, high] = std::minmax_element(tile.mesh.positions.begin(), tile.mesh.positions.end(),
                                               [](const glm::vec3& a, const glm::vec3& b) { return a.z < b.z; });
  tile.z_min = low->z;
  tile.z_max = high->z;
  if (HasYarnVolume(fabric)) {
    auto volume = std::make_shared<const YarnVolume>(yarns, fabric);
    tile.z_min = std::min(tile.z_min, volume->z_min());
    tile.z_max = std::max(tile.z_max, volume->z_max());
    tile.volume = std::move(volume);
  }
  return tile;
}

}  // namespace loom
