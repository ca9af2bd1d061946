#pragma once
// A knit tile's yarns as a volume of fibres (the lumislice paper §5.1.2, Fig. 6; issue 25):
// each yarn's cross-section (core/fabric/yarn_section.h) swept along its centre line and
// turned by the ply twist as it runs, so that a point's fibre density is its section's at
// the point's place in the section. The volume repeats with the tile. It is what the
// reference renderer and acquisition ray-march for knit yarns with plies or fuzz
// (core/acquire/volume_radiance.h); the derivation and what is approximated:
// docs/lumislice.md.
//
// The volume lives in the knit model's space (loop widths, where sections are round) and
// answers for tile-space points: extinction is per model unit of length, and ModelLength
// turns a tile-space distance into model units (the tile scales x and y differently).

#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "core/fabric/periodic_yarn.h"
#include "core/fabric/yarn_section.h"
#include "loom/v1/fabric.pb.h"

namespace loom {

// γ of eq. 5: extinction per yarn radius of path at fibre density 1. A ray through a
// single ply's centre meets an optical depth of about 10 (opaque); one through the
// yarn's outer tenth about 1 (the translucent edge the lumislice shows).
inline constexpr float kYarnOpticalDensity = 8.0f;

// Whether a knit's yarns are a volume: some yarn has plies > 1 or fuzz > 0. `fabric` has
// WithDefaults applied.
bool HasYarnVolume(const v1::FabricSpec& fabric);

struct VolumeSample {
  float extinction = 0.0f;  // σ_t per model unit of length: γ·ρ / R summed over yarns
  glm::vec3 fibre{};        // unit fibre direction (tile space) of the densest yarn here
  uint32_t material = 0;    // its FabricSpec.yarns index
};

class YarnVolume {
 public:
  // `yarns` as the knit model built them; `fabric` with WithDefaults applied.
  YarnVolume(const TileYarns& yarns, const v1::FabricSpec& fabric);

  // The volume at tile-space point `p` (any x, y: the tile repeats).
  VolumeSample Sample(glm::vec3 p) const;
  // The model-space length of tile-space vector `v`.
  float ModelLength(glm::vec3 v) const { return glm::length(v / model_to_tile_); }
  // The z range (tile units) outside which the density is 0.
  float z_min() const { return z_min_; }
  float z_max() const { return z_max_; }
  // A march step (tile units) that resolves the thinnest ply: a tenth of its radius.
  float step() const { return step_; }

 private:
  // One periodic yarn in model space: its centre line (points.back() is points.front()
  // plus the period), a transported normal per point, and the section's turn per point.
  struct Chain {
    std::vector<glm::vec3> points;
    std::vector<glm::vec3> normals;
    std::vector<float> turn;
    std::vector<uint32_t> segment_yarn;
  };
  // A segment of a chain, in one periodic copy (shifted by `shift`), near a grid cell.
  // Copies one tile apart in x continue each other: `along` numbers the segments on
  // through them, `across` tells copies shifted in y apart.
  struct Entry {
    uint32_t chain = 0;
    uint32_t segment = 0;
    glm::vec2 shift{0.0f};
    int32_t across = 0;
    int64_t along = 0;
  };

  std::vector<Chain> chains_;
  std::vector<YarnSection> sections_;   // per FabricSpec.yarns index
  std::vector<float> radius_;           // yarn radius, model units, per yarn
  glm::vec3 model_to_tile_{1.0f};
  glm::vec2 period_{1.0f};              // the tile in model units
  int grid_ = 1;                        // cells per side
  std::vector<uint32_t> cell_begin_;    // grid_² + 1 offsets into entries_
  std::vector<Entry> entries_;
  float z_min_ = 0.0f, z_max_ = 0.0f, step_ = 1.0f;
};

}  // namespace loom
