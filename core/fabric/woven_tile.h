#pragma once
// Woven fabric geometry (neural woven paper §3.1, §5.1; Daubert §4): warp threads along
// y and weft threads along x, each passing over and under the others as the weave
// matrix says.
//
// Model units are yarn pitches: warp i runs along x = i + 0.5, weft j along y = j + 0.5,
// and one weave repeat of n × n threads is the tile. At a crossing the upper thread's
// centre is at +crimp and the lower one's at -crimp; between crossings a thread's
// height follows a cardinal spline of tension 1 through its crossing heights: it rests
// flat on every crossing (a float lies flat along the threads it covers) and passes
// from +crimp to -crimp over one pitch on an S-curve whose steepest slope, half-way,
// is 3·crimp. The inclination angle is that steepest angle:
//   crimp = tan(inclination) / 3.
// The cross-section is lenticular (Kemp's and Hearle's model of a flattened yarn):
//   half-width a = (1 - gap_ratio) / 2, so gap_ratio of every pitch stays open: the
//     holes are real and a ray passes straight through between the threads;
//   half-thickness b = min(YarnSpec.radius, a, crimp · cos(inclination) /
//     kWovenCrimpClearance): the yarn radius where the crimp leaves room for it,
//     otherwise the yarn is pressed flatter (defaults: radius 0.25, inclination 20°
//     give b = 0.076, a lens about 6.6 times wider than thick).
// Why a lens and not an ellipse: where a warp and a weft both pass from over to under
// (the corners between four crossings) each is inclined by up to the full crimp slope,
// and their heights differ only linearly in the distance from the corner. An ellipse's
// thickness grows like the square root of the distance from its edge, faster than
// that, so elliptical warp and weft always overlap near the corners unless the gap is
// wide; a lens's thickness grows linearly and clears them down to gap 0.

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
