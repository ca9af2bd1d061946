#pragma once
// The shading parameters of a yarn (DESIGN.md "Yarn shading") from its YarnSpec.

#include "core/fabric/fabric_tile.h"
#include "loom/v1/fabric.pb.h"

namespace loom {

// The Kajiya-Kay exponent for fibre roughness α ∈ (0, 1]: n = 2/α² - 2, the
// Phong-Beckmann correspondence (a cosine lobe of exponent n has the width of a
// Beckmann distribution of roughness α), at least 1 so the roughest fibres still have
// a lobe: α = 1 → 1, 0.5 → 6, 0.2 → 48, 0.1 → 198. A roughness below 10⁻⁴ counts as
// 10⁻⁴ (n = 2·10⁸, narrower than any direction grid resolves): below ~10⁻²⁰ n would
// overflow to infinity and the lobe's normalisation to NaN.
float SpecularExponentFromRoughness(float roughness);

// yarn has WithDefaults applied.
YarnMaterial MakeYarnMaterial(const v1::YarnSpec& yarn);

}  // namespace loom
