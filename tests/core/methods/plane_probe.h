#pragma once
// A plane shaded by a fabric method on the GPU, each pixel against the method's C++
// evaluation for that pixel's texel, view and light: what the tests of each method
// use to show that its GLSL equals its C++.

#include <functional>
#include <vector>
#include <glm/glm.hpp>

#include "core/methods/fabric_method.h"

namespace loom {

// Radiance (rgb, per unit irradiance) and alpha of level 0's texel `texel` seen from
// `view` under a light from `light` (unit, tile frame).
using TexelEvaluation = std::function<glm::vec4(size_t texel, glm::vec3 view, glm::vec3 light)>;

struct PlaneProbe {
  int compared = 0;      // pixels compared (on the plane, off texel edges)
  double worst = 0.0;    // worst relative error over them and the three channels
};

// Renders a 96×64 plane (3×3 tiles, one directional light, no ambient, level 0,
// nearest texels, no MSAA) with `asset` uploaded in full floats, and compares.
// `resolution` is level 0's texels a side and `view_heights` the asset's.
PlaneProbe ProbePlane(const FabricAsset& asset, uint32_t resolution, const std::vector<float>& view_heights,
                      const TexelEvaluation& evaluate);

}  // namespace loom
