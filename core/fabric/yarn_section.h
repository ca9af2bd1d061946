#pragma once
// A yarn's cross-section as a fibre density (the lumislice paper §5.1.1, Fig. 6; issue
// 25): what a lumislice's voxels take their opacity from, and what a volumetric yarn is
// made of. Built from the yarn's spec after the procedural yarn model of Zhao et al.
// 2016 ("Fitting procedural yarn models for realistic cloth rendering"): `plies` round
// plies packed inside the yarn, each holding fibres with that model's cross-sectional
// distribution, and flyaway fibres outside the yarn for `fuzz`. What is taken from the
// model and what is not: docs/lumislice.md.
//
// Units: positions in yarn radii in the section's plane, the first ply's centre on +x at
// twist phase 0; density is the distribution's value, 1 − ε at a ply's centre, ε at its
// edge, 0 where no fibre is. The twist turns the section about the yarn's centre line as
// it runs along the yarn (`phase`, radians).

#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "loom/v1/fabric.pb.h"

namespace loom {

// Zhao et al.'s fibre distribution about a ply's centre: with r the distance over the
// ply's radius, p(r) = (1 − 2ε)·((e − e^r)/(e − 1))^β + ε for r ≤ 1, else 0. Loom uses
// one representative ε and β for every yarn (their fits from CT scans vary per yarn).
inline constexpr float kFibreDensityEpsilon = 0.1f;
inline constexpr float kFibreDensityBeta = 0.4f;
float PlyFibreDensity(float r);

struct YarnSection {
  uint32_t plies = 1;
  float ply_radius = 1.0f;  // yarn radii
  float ply_offset = 0.0f;  // ply centres from the yarn's centre, yarn radii
  float fuzz = 0.0f;        // flyaways reach 1 + fuzz yarn radii
  // The section's turn (radians) per yarn radius of length along the yarn: the ply
  // centres' helix (for one ply, the yarn's surface) leans by the twist angle ψ,
  // tan ψ / offset (offset 1 for one ply).
  float twist_rate = 0.0f;
  // The density is 0 beyond this distance from the yarn's centre: 1 + fuzz.
  float extent() const { return 1.0f + fuzz; }
};

// `yarn` with defaults applied (plies ≥ 1, fuzz in [0, 1]). Plies ≥ 2 are the largest
// equal circles that fit in the yarn touching their neighbours:
// r = sin(π/K) / (1 + sin(π/K)), offset 1 − r.  The twist rate follows `twist_degrees`.
YarnSection MakeYarnSection(const v1::YarnSpec& yarn);

// The density at `p` (yarn radii) with the section turned by `phase`: inside a ply its
// distribution; outside the yarn's radius the flyaways' fuzz·ε·e^{−3(|p| − 1)/fuzz},
// a twentieth of that at 1 + fuzz and 0 beyond.
float FibreDensity(const YarnSection& section, glm::vec2 p, float phase = 0.0f);

// The density over a resolution² grid covering [−extent, extent]² at phase 0, row y from
// −extent up, each cell the mean of 4×4 points in it: a lumislice's voxels.
std::vector<float> SectionDensityGrid(const YarnSection& section, int resolution);

}  // namespace loom
