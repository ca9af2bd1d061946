#pragma once
// Woven fabric geometry (neural woven paper §3.1, §5.1; Daubert §4): warp threads along
// y and weft threads along x, each passing over and under the others as the weave
// matrix says.
//
// Model units are yarn pitches: warp i runs along x = i + 0.5, weft j along y = j + 0.5,
// and one weave repeat of n × n threads is the tile. Threads rise and fall by ±crimp
// (crimp = tan(inclination) / 3) on cardinal splines through their crossings, with a
// lenticular cross-section of half-width (1 − gap_ratio) / 2, so the gaps are real
// holes. The profile, the section and why a lens: docs/geometry.md, "Weaves".

#include "core/fabric/periodic_yarn.h"
#include "loom/v1/fabric.pb.h"

namespace loom {

// Where a warp and a weft cross the corner between four crossings, each rises by
// 3·crimp per pitch of distance while a lens of half-width a ≈ 1/2 thickens by 2b/a per
// pitch from its edge, and a thread sloped at the inclination is 1/cos(inclination)
// thicker measured vertically: they clear when b ≤ 0.75 · crimp · cos(inclination).
// 1.5 (b ≤ 0.67 · crimp · cos) leaves a margin; measured over every weave at gaps 0 and
// 0.3 and inclinations 5° to 60°, no lens enters another.
inline constexpr float kWovenCrimpClearance = 1.5f;

// The warp and weft threads of one weave repeat (fabric has WithDefaults applied),
// samples_per_crossing spline samples from one crossing to the next.
TileYarns BuildWovenYarns(const v1::FabricSpec& fabric, int samples_per_crossing);

}  // namespace loom
