#pragma once
// The lumislice paper's yarn shadow (§5.2.1, eq. 10): light towards a yarn point is
// partly absorbed by every other yarn whose centre line passes within the yarn's reach
// R_y of it as the light sees them, between it and the light. With d the distance, in
// the light's view, from the point to that centre line,
//
//   T_y(d) = 1 − k₀ (1 − Π_i e^{−γρ(d, i)}) / (1 − Π_i e^{−γρ(0, i)}),   k₀ = 0.8,
//
// Π_i over the section's voxels along the light at offset d (here the chord's
// transmittance, averaged over the section's turn). The yarn near the point along its
// own course is the lumislice's business (its VRF holds that light's attenuation), so a
// segment does not shadow the points of its own chain within the lumislice's light
// path. Computed per segment (the paper: at slice vertices) and light: a directional
// light's view is orthographic, a point light's perspective from it (d then measured at
// the shadowing yarn's distance from the light). T_y(d) is each yarn's
// Lumislice::shadow_profile.

#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "core/methods/lumislice/lumislice_table.h"
#include "core/scene/scene_light.h"

namespace loom {

struct ShadowSegment {
  glm::vec3 start{}, end{};
  float radius = 0.0f;     // world units
  uint32_t yarn = 0;       // index into the profiles
  uint32_t chain = 0;      // segments of one chain follow each other
  float arc = 0.0f;        // the chain's length before `start`, world units
};

struct YarnShadowProfiles {
  std::vector<std::vector<float>> profile;  // per yarn
  std::vector<float> extent;                // per yarn, yarn radii
  // Along its own chain, a segment is not shadowed by yarn closer than this many yarn
  // radii (the lumislice's light path).
  float own_chain_radii = 0.0f;
};

// T_y at each segment's midpoint for `light`: the product over the segments that
// shadow it (1 where a point light does not see the segment in front of it).
std::vector<float> YarnShadows(const std::vector<ShadowSegment>& segments, const YarnShadowProfiles& profiles,
                               const SceneLight& light);

}  // namespace loom
