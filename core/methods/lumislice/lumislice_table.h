#pragma once
// A yarn's lumislice (the lumislice paper §5.1.1, eq. 4–8, and §5.2.2, eq. 11; issue 25):
// the voxels of one cross-section of the yarn (core/fabric/yarn_section.h) with their
// fibre density, the paper's opacity table, and per light direction their voxel
// reflectance function, the paper's colour table. The light reaches a voxel through
// the straight twisted yarn around it (eq. 5), and scattered between its fibres (I_msp,
// fibre walks: core/acquire/fibre_walk.h); the voxel reflects it with the volume's fibre
// shading (core/acquire/volume_radiance.h), so slices composited along a yarn give what
// the reference's march gives. Levels of detail halve the resolution and
// double the voxel by eq. 11 down to 1×1 (the paper samples the finest level below 8×8;
// that measured worse, docs/lumislice.md). What is kept and dropped from the paper, and
// the derivation: docs/lumislice.md.
//
// The slice's frame: x and y the section's axes at twist phase 0 (yarn radii), z along
// the yarn. Light directions are (cos φ cos θ, cos φ sin θ, sin φ), θ the longitude
// in [0, 2π) over kLumisliceLongitudes, φ the altitude in [−π/2, π/2] over
// kLumisliceAltitudes with both ends. Voxel (x, y) of a level is index y·resolution + x,
// row y from −extent up.

#include <cstddef>
#include <functional>
#include <glm/glm.hpp>
#include <vector>

#include "core/fabric/fabric_tile.h"
#include "core/fabric/yarn_section.h"
#include "loom/v1/fabric.pb.h"

namespace loom {

inline constexpr int kLumisliceLongitudes = 32;
inline constexpr int kLumisliceAltitudes = 21;
inline constexpr int kLumisliceDirections = kLumisliceLongitudes * kLumisliceAltitudes;

// Table direction `longitude` + kLumisliceLongitudes·`altitude`, in the slice's frame.
glm::vec3 LumisliceLightDirection(int direction);

struct LumisliceLevel {
  int resolution = 0;   // voxels a side
  float voxel = 0.0f;   // a voxel's side and thickness along the yarn, yarn radii
  std::vector<float> density;  // ρ per voxel: the opacity table
  // Per direction (outer) and voxel: rgb the diffuse VRF without ρ, f_d(l, t)·T_l + I_msp
  // (core/acquire/fibre_walk.h); a the light's transmittance T_l to the voxel (eq. 5),
  // what the specular lobe kept in the renderer is scaled by.
  std::vector<glm::vec4> vrf;

  size_t voxel_count() const { return static_cast<size_t>(resolution) * resolution; }
  const glm::vec4& at(int direction, size_t voxel) const { return vrf[direction * voxel_count() + voxel]; }
};

// Eq. 10's yarn shadow T_y(d) (core/render/yarn_shadow.h) at kYarnShadowProfileSamples
// offsets d = extent·k/(samples − 1) yarn radii from the centre line: 1 − k₀ (1 − T(d)) /
// (1 − T(0)), T(d) the transmittance of the section's chord at d averaged over its turn.
inline constexpr float kYarnShadowStrength = 0.8f;  // k₀
inline constexpr int kYarnShadowProfileSamples = 64;
std::vector<float> YarnShadowProfile(const YarnSection& section, float optical_density);

struct Lumislice {
  YarnSection section;
  float optical_density = 0.0f;      // γ: extinction per yarn radius at density 1
  std::vector<LumisliceLevel> levels;  // levels[0] the finest, down to 1×1
  std::vector<float> shadow_profile;   // YarnShadowProfile(section, optical_density)

  // Bytes as stored: half floats, the density and four channels per direction.
  size_t StoredBytes() const;
};

struct LumisliceSettings {
  int resolution = 32;         // of the finest level: a power of two in [8, 256]
  // How far (yarn radii) light runs along the straight yarn to a voxel at most: about a
  // knit loop's leg, beyond which the real yarn bends away.
  float max_light_path = 4.0f;
  // Fibre walks per voxel that estimate the light scattered between fibres (I_msp).
  int walks = 64;
  unsigned threads = 0;        // 0: every core
};

// The yarn's lumislice, every level, γ = kYarnOpticalDensity (the volume's). `section`
// and `material` describe the same yarn. I_msp comes from fibre walks through the straight
// twisted yarn within max_light_path of the slice. progress(fraction) as the finest level's
// voxels finish.
Lumislice BuildLumislice(const YarnSection& section, const YarnMaterial& material, const LumisliceSettings& settings,
                         const std::function<void(double)>& progress = {});

// The lumislice of each of `fabric`'s yarns (WithDefaults applied), by FabricSpec.yarns
// index.
std::vector<Lumislice> BuildFabricLumislices(const v1::FabricSpec& fabric, const LumisliceSettings& settings);

// The light's transmittance (eq. 5) from `light` to section point `p` (yarn radii, z = 0)
// through the straight yarn twisted at section.twist_rate, marched in steps of `step`
// (yarn radii) up to `max_path` yarn radii or out of the section's extent.
float LumisliceLightTransmittance(const YarnSection& section, float optical_density, glm::vec2 p, glm::vec3 light,
                                  float max_path, float step);
// The step BuildLumislice marches at: a sixth of a ply's radius, or half a voxel of the
// finest level where that is finer (the plies' edges are steep).
float LumisliceMarchStep(const YarnSection& section, int resolution);

// Eq. 11: half the resolution, twice the voxel: ρ' the mean of each 2×2 block, the VRF
// its density-weighted mean (the plain mean where the block is empty).
LumisliceLevel HalveLumisliceLevel(const LumisliceLevel& fine);

}  // namespace loom
