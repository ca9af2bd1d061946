#pragma once
// Loom's defaults. In spec files a zero (or absent) value means "the default";
// WithDefaults makes every default explicit, so later stages never see a zero that
// means something else. Fields where zero is a real value (gap ratio, jitter,
// twist, seeds) keep it. Defaults are chosen for the standard scene (DESIGN.md
// "model no more than a scene needs" refines them per scene).

#include <cstdint>

#include "loom/v1/animation.pb.h"
#include "loom/v1/fabric.pb.h"
#include "loom/v1/precompute.pb.h"
#include "loom/v1/scene.pb.h"

namespace loom {

v1::FabricSpec WithDefaults(v1::FabricSpec fabric);
v1::PrecomputeSettings WithDefaults(v1::PrecomputeSettings settings);
v1::RenderSettings WithDefaults(v1::RenderSettings settings);
// Applies the defaults of every nested fabric, precompute and render setting too.
v1::SceneSpec WithDefaults(v1::SceneSpec scene);
// Loop spacings 1, the cloth along +x (courses) and +y (wales), 25 frames a
// second, the fabric's defaults.
v1::AnimationSpec WithDefaults(v1::AnimationSpec animation);
// The frames after the first an animation records, ⌈duration × rate⌉ (a product
// within 10⁻³ of a whole number counts as it): frame k at k / rate seconds. 0
// for a duration or rate that is not positive and finite.
uint64_t AnimationFrames(const v1::AnimationSpec& animation);

// The methods whose assets are tables over the stored directions (tabulated, and
// factored, which factors the table): they keep every sample per level while they
// build, and interpolate the stored views themselves (their own defaults and cap).
bool IsTableMethod(v1::FabricMethod method);

// Whether a precompute of `fabric` acquires light from behind the cloth:
// settings.transmission if set, else whether a yarn transmits (microflake shading).
bool AcquiresTransmission(const v1::FabricSpec& fabric, const v1::PrecomputeSettings& settings);

// The smallest tile of a knit pattern, in loops: wales and courses of a tile are
// multiples of it. Stockinette and reverse 1×1, garter 1×2, rib
// (rib_knit + rib_purl)×1, seed 2×2. Unspecified counts as stockinette.
struct KnitRepeat {
  uint32_t wales = 1;
  uint32_t courses = 1;
};
KnitRepeat KnitPatternRepeat(const v1::KnitSpec& knit);

// A satin move m is valid for repeat n when 1 < m < n-1 and gcd(m, n) = 1: every
// row and column then has exactly one interlacing and no two touch.
bool IsValidSatinMove(uint32_t n, uint32_t m);
// The smallest valid move for repeat n, or 0 if n has none (n < 5, or e.g. 6).
uint32_t SmallestSatinMove(uint32_t n);

}  // namespace loom
