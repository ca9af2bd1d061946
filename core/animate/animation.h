#pragma once
// An AnimationSpec run: the knit cloth, pins and colliders it asks for, the knit
// simulation stepped through its duration, and the cloth's points recorded at
// every frame. This is what the `animate` job and `loom-lab animate` run; the
// sequence writers (core/animate/cloth_sequence_io.h) turn the result into files.

#include <functional>
#include <glm/glm.hpp>
#include <vector>

#include "core/animate/knit_cloth.h"
#include "core/animate/knit_simulation.h"
#include "core/scene/scene_geometry.h"
#include "loom/v1/animation.pb.h"

namespace loom::animate {

struct ClothAnimation {
  KnitCloth cloth;  // the topology; its positions are frame 0's
  float frames_per_second = 25.0f;
  // Frame k is the cloth at k / frames_per_second seconds, k = 0 … ⌈duration × rate⌉.
  std::vector<std::vector<glm::vec3>> frames;
  // The spec's colliders, where it placed them, and how far each had moved at
  // every frame ([collider][frame]).
  std::vector<Collider> colliders;
  std::vector<std::vector<glm::vec3>> collider_tracks;
  SimulationCounts counts;
  float min_collider_distance = 0.0f;  // over every step (+∞ without colliders)
  float min_self_distance = 0.0f;      // over every step (+∞ while the cloth never met itself)
  double simulation_seconds = 0.0;     // wall-clock time of the stepping
};

// The spec's colliders (the spec with defaults applied and validated): its mesh
// colliders read through `meshes` and built (errors name the collider).
std::vector<Collider> BuildColliders(const v1::AnimationSpec& spec, const MeshTextResolver& meshes);

// Loom's default mechanics with what the spec sets in place of the defaults.
KnitMechanics Mechanics(const v1::KnitMechanicsSpec& spec);

// The spec is validated first (Error(kInvalidArgument) naming each bad field).
// progress(done, total) after each frame; `threads` for the contact search (0:
// every core); `meshes` reads the mesh colliders' files (none: a mesh collider
// may only be a built-in shape).
ClothAnimation RunAnimation(const v1::AnimationSpec& spec,
                            const std::function<void(size_t done, size_t total)>& progress = {}, unsigned threads = 0,
                            const MeshTextResolver& meshes = {});

}  // namespace loom::animate
