#pragma once
// Radiance samples made up for the fabric-method tests.

#include <cstdint>

#include "core/acquire/radiance_samples.h"

namespace loom {

// Samples whose radiance varies smoothly with view and light and differs per texel
// and channel (a tint per texel); with `holes`, every fifth (texel, view) pair empty.
RadianceSamples SyntheticSamples(uint32_t resolution, uint32_t views, uint32_t lights, bool holes);

// `samples` with view heights that differ per view: `base` at the zenith, rising by
// up to half of it towards the horizon and differing with the azimuth, as a view-depth
// sampling plane's do.
RadianceSamples WithViewHeights(RadianceSamples samples, float base);

}  // namespace loom
