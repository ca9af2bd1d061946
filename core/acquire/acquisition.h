#pragma once
// Radiance acquisition (Daubert 2001 §4, Fig. 2-3; DESIGN.md "Core engine" 2):
// from one periodic fabric tile, the RadianceSamples that fitting turns into the
// BRDF array.
//
// For each view v (HemisphereGridDirections(view_directions)), each texel's
// s×s stratified sub-samples (s = supersampling, jittered from the seed, the same
// pattern for every view) are points of the view's sampling plane z = h(v), and the
// rays through them along −v are cast from the top face z = z_max + ε into the
// tile repeated over the plane (PeriodicScene), so holes show what lies below and
// beside. h(v) is the top face itself (SAMPLING_PLANE_TOP) or the mean z at which
// the view's rays from the top face first meet yarn (SAMPLING_PLANE_VIEW_DEPTH; a
// first pass of primary rays, the same jittered pattern). Per (texel, view):
// alpha = covered sub-samples / s².
// Per texel: the hit normals of every view and sub-sample are summed and
// normalised (the paper's AverageNormals); the tangent is the x axis made
// perpendicular to that normal (the paper's binormal n × x, then tangent b × n).
// Per (texel, view, light): the mean over the covered sub-samples of
//   L = f_r(l, v) · E · cos θ_l · visible(l)  +  ρ_d/π · E_ind(l)
// with exact shadow rays, f_r the yarn BRDF (core/acquire/yarn_shading.h) and
// E_ind the indirect irradiance after settings.indirect_bounces diffuse bounces
// (core/acquire/indirect_light.h); 0 where alpha is 0.
//
// Light side: the lights are the grid's directions (z > 0) or, for LightSide::kBack,
// the same directions mirrored below the cloth (z < 0), whose light reaches the
// viewer's side through holes and through yarns that transmit (yarn_radiance.h).
//
// Light convention: every light is directional with unit irradiance E = 1 on a
// surface facing it, so radiance = f_r · E · cos θ_l, and a white Lambertian surface
// lit head-on has radiance 1/π.
//
// Determinism: each texel is one work item with its own random streams, so the
// samples are bit-identical for the same tile and settings whatever the thread
// count or schedule. Every sample value is finite: a non-finite value (which
// validated input should never produce) is stored as 0 and counted.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string_view>

#include "core/acquire/radiance_samples.h"
#include "core/fabric/fabric_tile.h"
#include "loom/v1/precompute.pb.h"

namespace loom {

// fraction in [0, 1], non-decreasing; stage says what runs now. Called on the
// thread that called Acquire. Throwing from it cancels the acquisition (the
// exception propagates out of Acquire).
using AcquireProgress = std::function<void(double fraction, std::string_view stage)>;

struct AcquireStats {
  double seconds = 0;
  uint64_t rays = 0;              // every ray cast: primary, shadow and gather
  unsigned threads = 0;
  int tiles_x = 0, tiles_y = 0;   // copies of the tile in the ray-casting scene
  uint32_t light_batches = 0;     // see AcquireOptions::indirect_memory_bytes
  uint64_t non_finite_values = 0; // replaced by 0; always 0 for validated input

  double rays_per_second() const { return seconds > 0 ? static_cast<double>(rays) / seconds : 0.0; }
};

// How to run (not what to compute: the samples do not depend on these).
struct AcquireOptions {
  unsigned threads = 0;  // 0: every core
  // Indirect light holds about 3 × vertices × lights RGB floats while it is
  // computed; past this many bytes the lights are processed in batches (each batch
  // recasts the primary rays).
  size_t indirect_memory_bytes = size_t{256} << 20;
};

enum class LightSide { kFront, kBack };

// Validates `settings` (core/spec/validate.h; unset fields take their defaults)
// and the tile (consistent sizes, indices in range, finite values, albedos in
// [0, 1] summing to at most 1, geometry inside [z_min, z_max]) before any work,
// throwing Error(kInvalidArgument) that names the field.
RadianceSamples Acquire(const FabricTile& tile, const v1::PrecomputeSettings& settings,
                        const AcquireProgress& progress = {}, AcquireStats* stats = nullptr,
                        const AcquireOptions& options = {}, LightSide side = LightSide::kFront);

}  // namespace loom
