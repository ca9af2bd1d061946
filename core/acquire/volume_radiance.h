#pragma once
// Light in a tile's yarn volume (core/fabric/yarn_volume.h): the lumislice paper's
// emission–absorption model (§5.1, eq. 4–9) marched along rays, what the reference
// renderer and acquisition see of knit yarns with plies or fuzz. Along a view ray
//
//   L = Σ_k T_k (1 − e^{−σ_k h}) · [Σ_lights E f_v(l, v, t_k) T_l(p_k) + I_ms(p_k)],
//
// T_k the transmittance from the ray's entry to step k, σ_k the extinction there, h the
// step, T_l(p) the transmittance from p towards the light (eq. 5), t_k the fibre
// direction. f_v is the fibre's diffuse scattering with its physical albedo plus its
// Kajiya–Kay specular lobe; I_ms the light scattered between fibres (the paper's I_msp),
// estimated by random walks (core/acquire/fibre_walk.h) from one step drawn by its
// weight. Derivation and limits: docs/lumislice.md.
//
// Rays are in tile space; they end where they leave the volume's z slab (or after
// kMaxHorizontalTiles of travel for one along it). Steps start at `jitter` ∈ [0, 1) of a
// step from the ray's entry into the slab.

#include <cstdint>
#include <glm/glm.hpp>
#include <optional>
#include <vector>

#include "core/acquire/random_stream.h"
#include "core/fabric/fabric_tile.h"
#include "core/fabric/yarn_volume.h"

namespace loom {

// Version of the light model in the volume (this unit and core/acquire/fibre_walk.h):
// part of the cache key of a fabric with a yarn volume (core/spec/fabric_key.h), so that
// changing the model invalidates the assets acquired from it, and only those.
inline constexpr uint32_t kVolumeLightModelVersion = 3;

// f_v(l, v, t) = f_d(l, v, t) + 2 ρ_s N(p) ψ^p: the diffuse scattering of
// core/acquire/fibre_walk.h and the Kajiya–Kay lobe (ψ as in core/acquire/kajiya_kay_brdf.h),
// scaled so that a thick flat bed of fibres reflects it as the yarn's surface does.
glm::vec3 FibreScattering(const YarnMaterial& material, glm::vec3 fibre, glm::vec3 l, glm::vec3 v);

// Below this transmittance a march stops: what lies further adds less than 10⁻⁴.
inline constexpr float kMinVolumeTransmittance = 1e-4f;
// A ray that runs along the slab stops after this much horizontal travel.
inline constexpr float kMaxHorizontalTiles = 16.0f;

struct VolumeStep {
  glm::vec3 position{};  // tile space
  VolumeSample sample;
  float weight = 0.0f;   // T_k (1 − e^{−σ_k h})
};

// The ray's [t_enter, t_exit] inside the slab; empty (enter > exit) if it misses it.
glm::vec2 SlabInterval(const YarnVolume& volume, glm::vec3 origin, glm::vec3 direction);

// Calls visit(const VolumeStep&) for every step with fibres; returns the transmittance
// left where the ray leaves the slab (0 once below kMinVolumeTransmittance).
template <class Visit>
float MarchVolume(const YarnVolume& volume, glm::vec3 origin, glm::vec3 direction, float jitter, Visit&& visit) {
  const glm::vec2 span = SlabInterval(volume, origin, direction);
  const float h = volume.step();
  const float length_scale = volume.ModelLength(direction) * h;
  float transmittance = 1.0f;
  for (float t = span.x + jitter * h; t < span.y; t += h) {
    VolumeStep step;
    step.position = origin + t * direction;
    step.sample = volume.Sample(step.position);
    if (step.sample.extinction <= 0.0f) continue;
    const float passed = std::exp(-step.sample.extinction * length_scale);
    step.weight = transmittance * (1.0f - passed);
    visit(step);
    transmittance *= passed;
    if (transmittance < kMinVolumeTransmittance) return 0.0f;
  }
  return transmittance;
}

// The tile's volume as a medium for fibre walks (core/acquire/fibre_walk.h).
struct TileVolumeMedium {
  const YarnVolume& volume;
  VolumeSample Sample(glm::vec3 p) const { return volume.Sample(p); }
  float ModelLength(glm::vec3 v) const { return volume.ModelLength(v); }
  float step() const { return volume.step(); }
  glm::vec2 Interval(glm::vec3 origin, glm::vec3 direction) const { return SlabInterval(volume, origin, direction); }
};

// Draws one of a march's steps with probability weight / Σ weights (a weighted
// reservoir of one): what a ray's I_ms is estimated from, times Σ weights.
class WeightedStep {
 public:
  void Offer(const VolumeStep& step, RandomStream& random) {
    total_ += step.weight;
    if (random.Uniform() * total_ < step.weight) chosen_ = step;
  }
  float total() const { return total_; }
  const std::optional<VolumeStep>& chosen() const { return chosen_; }

 private:
  float total_ = 0.0f;
  std::optional<VolumeStep> chosen_;
};

// T from `origin` along `direction` to where the ray leaves the slab.
float VolumeTransmittance(const YarnVolume& volume, glm::vec3 origin, glm::vec3 direction, float jitter);

// T_l over the tile for one light direction: what acquisition looks up at its view
// rays' steps for every light instead of marching each. Columns start on the slab's face
// towards the light, on a grid periodic in x and y, and march into the slab along −l,
// each recording T and the optical depth τ where it crosses the grid's z levels; a
// point's T_l is the geometric mean of T and e^(−τ) interpolated from the columns through
// its neighbourhood (bilinearly across, linearly in z): across a yarn's edge the one is
// too bright and the other too dark (docs/lumislice.md). Columns and levels are
// kTransmittanceNodeSteps march steps apart; tests/core/fabric/yarn_volume_test.cpp
// bounds the difference from marching.
inline constexpr float kTransmittanceNodeSteps = 2.0f;
class LightTransmittance {
 public:
  // The grid for unit tile-space direction `light` (l.z ≠ 0), every node lit until marched.
  LightTransmittance(const YarnVolume& volume, glm::vec3 light);
  size_t column_count() const { return static_cast<size_t>(size_.x) * size_.y; }
  // Marches columns [first, first + count) (independent: any split and order).
  void MarchColumns(const YarnVolume& volume, size_t first, size_t count);
  // T_l at tile-space point p.
  float operator()(glm::vec3 p) const;

 private:
  glm::vec3 light_{0.0f};
  glm::ivec3 size_{1};   // columns across x and y, levels in z
  float face_ = 0.0f;    // z of the slab's face towards the light
  float z_min_ = 0.0f, z_step_ = 1.0f;
  std::vector<glm::vec2> values_;  // (T, τ) per column (x fastest, then y), its levels from z_min up
};

}  // namespace loom
