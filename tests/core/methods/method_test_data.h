#pragma once
// Radiance samples made up for the fabric-method tests.

#include <cstdint>

#include "core/acquire/radiance_samples.h"

namespace loom {

// Samples whose radiance varies smoothly with view and light and differs per texel
// and channel (a tint per texel); with `holes`, every fifth (texel, view) pair empty.
RadianceSamples SyntheticSamples(uint32_t resolution, uint32_t views, uint32_t lights, bool holes);

}  // namespace loom
