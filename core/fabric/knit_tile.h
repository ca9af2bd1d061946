#pragma once
// Knitted fabric geometry after the lumislice paper (§3, Fig. 3): every loop is a few
// key points in its (u, v) cell, offset out of the fabric plane and joined into one
// continuous yarn per course (row of loops) by a cardinal spline.
//
// Model units are loop widths: loop (wale i, course j) occupies the cell
// [i, i+1] × [j h, (j+1) h] with h = 1 / loop_aspect, z up towards the fabric's face.
// The paper's six key points, in cell units (its n0..n3 are the cell's corners with v
// pointing down its figure), are
//   k0 sinker (0, -0.35 h)   k1 foot (0.375, 0)         k2 shoulder (0.125, h)
//   k3 head   (0.5, 1.35 h)  k4 shoulder (0.875, h)     k5 foot (0.625, 0),
// so a loop's head reaches into the cell above and its sinker into the cell below:
// that is where the loops of adjacent courses interlock, the head of the lower loop
// wrapping round the feet of the upper one. Loom keeps that layout and adds what the
// paper leaves to "offsets that avoid collisions" (its Fig. 4):
// - z offsets: in a knit stitch the new loop is pulled through the old one from the
//   back, so the legs lie in front and the sinker and the head of the loop below lie
//   behind; a purl stitch is the mirror image in z. The lower half of a loop (feet,
//   sinker) follows its own stitch and the upper half (shoulders, head) the stitch of
//   the loop above, which is the one it wraps round. z offsets scale with the yarn
//   radius, so thin yarns make a thin fabric.
// - the sinker k0 is split into two key points, one per neighbouring loop, so a sinker
//   between a knit and a purl loop (rib, seed) can pass from the back to the front.
// - the key points were placed by a search that maximised the smallest clearance
//   between yarns and the smallest radius of curvature (over stockinette, garter, 1×1
//   and 2×2 rib and seed tiles of at least 2 wales × 3 courses, at yarn radius 0.085)
//   starting from the paper's layout, at loop aspects 0.5 to 2 in steps of 0.25; other
//   aspects interpolate linearly.
//
// Non-interpenetration: where loops interlock, four yarns (two shoulders of the loop
// below, two feet of the loop above) cross the same height at the same depth within
// one wale, so no symmetric loop fits a yarn radius of 1/8 of the loop width or more
// (the jamming limit of plain knits); short loops (large aspect) also stack the head
// of one course close to the sinker two courses up. Up to kMaxKnitYarnRadius every
// pair of yarns stays at least 2.09·radius apart (at aspect 2; 2.56·radius at aspects
// up to 1.5) and no yarn bends tighter than its radius. Random loop offsets
// (loop_jitter) eat into that margin.

#include "core/fabric/periodic_yarn.h"
#include "core/spec/limits.h"  // kMaxKnitYarnRadius
#include "loom/v1/fabric.pb.h"

namespace loom {

// The course yarns of one knit tile (fabric has WithDefaults applied; every yarn
// radius at most kMaxKnitYarnRadius): wales × courses loops, samples_per_segment
// spline samples between consecutive key points. model_to_tile maps the loop cell to
// (1/wales) × (1/courses) of the tile, and z and the radius by 1/wales like x (so the
// tile is the fabric stretched in y by wales·loop_aspect/courses; it is undistorted when
// the tile is mapped onto a surface patch of that aspect).
TileYarns BuildKnitYarns(const v1::FabricSpec& fabric, int samples_per_segment);

}  // namespace loom
