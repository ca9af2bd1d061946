#pragma once
// Knitted fabric geometry after the lumislice paper (§3, Fig. 3): every loop is a few
// key points in its (u, v) cell, offset out of the fabric plane and joined into one
// continuous yarn per course (row of loops) by a cardinal spline.
//
// Model units are loop widths: loop (wale i, course j) occupies the cell
// [i, i+1] × [j h, (j+1) h] with h = 1 / loop_aspect, z up towards the fabric's face.
// Up to kMaxKnitYarnRadius no two yarns interpenetrate and no yarn bends tighter than
// its radius; random loop offsets (loop_jitter) eat into that margin. The key points,
// their offsets and why: docs/geometry.md, "Knits".

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
