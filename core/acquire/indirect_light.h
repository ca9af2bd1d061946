#pragma once
// Indirect diffuse light between yarns (issue 3: 0-2 bounces, default 1), as
// irradiance per mesh vertex and light, interpolated linearly over triangles.
// Daubert 2001 §4 likewise lights the mesh per vertex. Indirect light is diffuse,
// so it does not depend on the view: it is computed once per light and reused by
// every view and every texel.
//
// Method. The light-independent part is computed once: from each vertex, 64
// cosine-distributed rays (8×8 strata, jittered from PrecomputeSettings.seed) find
// what the vertex sees. A ray that hits a front face with diffuse albedo ρ adds
// ρ/64 times the hit's barycentric weights to the vertex's gather row, so that
//   W[i][j] = (1/64) Σ_{rays of i that hit a triangle with vertex j} ρ · w_j   (RGB)
// is a Monte-Carlo estimate of the irradiance operator: irradiance at i from
// surfaces whose outgoing radiance is ρ/π × (their irradiance). Then for the lights:
//   E₀[j] = max(0, n_j·l) · visible(j, l)   direct irradiance (one shadow ray)
//   E_k   = W · E_{k−1}                     after k diffuse bounces
//   E_ind = E₁ + … + E_b                    what Interpolate returns
// Approximations, each fixed by the tile, the settings and the seed:
// - irradiance is linear across a triangle, so a shadow edge in E₀ is blurred
//   over the triangles it crosses (E₀ feeds only indirect light; direct light at the
//   sample points has exact shadow rays);
// - each bounce's gather is a 64-ray estimate per vertex;
// - light leaves a surface diffusely on every bounce: the fibre lobe reflects only
//   direct light;
// - rays that stay in the slab past PeriodicScene::kMaxContinuations count as escaping.
// Memory: the gather rows hold at most 3·64 entries per vertex (16 bytes each),
// the irradiance vertices × lights RGB floats.

#include <cstdint>
#include <functional>
#include <glm/glm.hpp>
#include <vector>

#include "core/acquire/periodic_scene.h"
#include "core/fabric/fabric_tile.h"

namespace loom {

// Indirect irradiance per (vertex, light) for one set of lights.
struct VertexIrradiance {
  size_t light_count = 0;
  std::vector<glm::vec3> values;  // [vertex · light_count + light]
  uint64_t rays = 0;              // shadow rays cast to compute it

  // The irradiance at a hit on `mesh`, for every light, into out[0, light_count).
  void Interpolate(const TriangleMesh& mesh, const RayHit& hit, glm::vec3* out) const;
};

class IndirectLight {
 public:
  // Casts the gather rays (bounces ≥ 1). progress(fraction) on the calling thread.
  IndirectLight(const FabricTile& tile, const PeriodicScene& scene, uint32_t bounces, uint64_t seed,
                unsigned threads, const std::function<void(double)>& progress);

  VertexIrradiance Irradiance(const std::vector<glm::vec3>& lights, unsigned threads,
                              const std::function<void(double)>& progress) const;

  uint64_t gather_rays() const { return gather_rays_; }

  static constexpr uint32_t kGatherStrata = 8;  // 8×8 = 64 rays per vertex

 private:
  struct Entry {
    uint32_t vertex;
    glm::vec3 weight;
  };

  const FabricTile& tile_;
  const PeriodicScene& scene_;
  uint32_t bounces_;
  std::vector<glm::vec3> normals_;  // unit vertex normals; zero where the mesh's vanish
  // CSR rows of W: row i is entries_[row_start_[i] .. row_start_[i+1]), by vertex.
  std::vector<size_t> row_start_;
  std::vector<Entry> entries_;
  uint64_t gather_rays_ = 0;
};

}  // namespace loom
