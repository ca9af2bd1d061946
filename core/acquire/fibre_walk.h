#pragma once
// Multiple scattering between fibres (the lumislice paper's I_msp, eq. 4; issue 25):
// random walks through a fibre volume, what the reference, acquisition and the lumislice
// table add to the light a fibre gets straight from the lights.
//
// A fibre scatters the diffuse part of the light it stops evenly into all directions,
// with the physical albedo α of its yarn (FibreAlbedo, ≤ 1) and its cross-section
// towards the light: per unit of extinction, light from l leaves towards any v as
//   f_d(l, v, t) = α (4/π) sin(t, l) / (4π) = α sin(t, l) / π²,
// (4/π the inverse of sin's mean over the sphere, so that light from every direction
// alike is scattered with α). The specular lobe scatters once only. A walk starts at a
// scattering point p seen along v: it draws the direction ω the light came from evenly,
// flies to where that light was scattered (free-flight sampling of the march's optical
// depth), and there asks the caller for the light the lights give that point; then it
// scatters on, Russian roulette ending it. Derivation and limits: docs/lumislice.md.
//
// A medium is anything with VolumeSample Sample(p), float ModelLength(v), float step()
// and glm::vec2 Interval(origin, direction) (the ray's part inside it; empty if
// enter > exit), as TileVolumeMedium (core/acquire/volume_radiance.h).

#include <cmath>
#include <glm/glm.hpp>
#include <optional>
#include <vector>

#include "core/acquire/random_stream.h"
#include "core/fabric/fabric_tile.h"
#include "core/fabric/yarn_volume.h"

namespace loom {

// α per channel from the yarn's diffuse albedo ρ_d: the single-scattering albedo of a
// half-space of evenly scattering fibres whose reflectance over every order is ρ_d
// (Christensen and Burley 2015's inversion).
glm::vec3 FibreAlbedo(glm::vec3 diffuse_albedo);

// f_d(l, ·, t) = α sin(t, l) / π², α = FibreAlbedo(the yarn's diffuse albedo): callers
// take α once per material, out of their loops over lights.
glm::vec3 FibreDiffuseScattering(glm::vec3 fibre_albedo, glm::vec3 fibre, glm::vec3 l);

// A direction drawn evenly over the sphere.
glm::vec3 UniformSphereDirection(RandomStream& random);

// A walk ends after this many scattering events whatever roulette says.
inline constexpr int kMaxWalkEvents = 256;

struct FreeFlightEvent {
  glm::vec3 position{};
  VolumeSample sample;
};

// Where a ray from `origin` along `direction` has met optical depth `depth` (a step's
// point; steps start at `jitter` of a step), or nothing if it leaves the medium first.
template <class Medium>
std::optional<FreeFlightEvent> FreeFlight(const Medium& medium, glm::vec3 origin, glm::vec3 direction, float depth,
                                          float jitter) {
  const glm::vec2 span = medium.Interval(origin, direction);
  const float h = medium.step();
  const float length_scale = medium.ModelLength(direction) * h;
  float reached = 0.0f;
  for (float t = span.x + jitter * h; t < span.y; t += h) {
    const glm::vec3 p = origin + t * direction;
    const VolumeSample sample = medium.Sample(p);
    reached += sample.extinction * length_scale;
    if (reached >= depth) return FreeFlightEvent{p, sample};
  }
  return std::nullopt;
}

// One walk from scattering point (`start`, `at`): calls visit(q, sample at q, throughput)
// at each event q. The light scattered more than once that leaves the start towards any
// direction, per unit of extinction there, is Σ throughput · (what the lights give q per
// unit of extinction by f_d: f_d · E · T_l summed over lights), an unbiased estimate.
template <class Medium, class Visit>
void WalkFibres(const Medium& medium, const std::vector<YarnMaterial>& materials, glm::vec3 start,
                const VolumeSample& at, RandomStream& random, Visit&& visit) {
  constexpr float kFourOverPi = 1.27323954f;
  glm::vec3 throughput(1.0f), position = start;
  VolumeSample sample = at;
  for (int event = 0; event < kMaxWalkEvents; ++event) {
    const glm::vec3 omega = UniformSphereDirection(random);
    const float sin_omega = glm::length(glm::cross(sample.fibre, omega));
    throughput *= FibreAlbedo(materials[sample.material].diffuse_albedo) * (kFourOverPi * sin_omega);
    const float keep = std::fmin(1.0f, std::fmax(throughput.r, std::fmax(throughput.g, throughput.b)));
    if (keep <= 0.0f || random.Uniform() >= keep) break;
    throughput /= keep;
    const float depth = -std::log(1.0f - random.Uniform());
    const std::optional<FreeFlightEvent> next = FreeFlight(medium, position, omega, depth, random.Uniform());
    if (!next) break;
    position = next->position;
    sample = next->sample;
    visit(position, sample, throughput);
  }
}

}  // namespace loom
