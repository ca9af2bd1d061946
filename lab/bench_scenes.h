#pragma once
// The bench scene set (issue 7, DESIGN.md "Measurement protocol"): a small JSON
// file (bench/scenes/bench_set.json) listing fabrics, tilts, distances and curved
// shapes, expanded here into plain SceneSpecs, one per fabric × (tilt × distance +
// curved shape). Writing the set instead of 60 scene files keeps the geometry rule
// in one place:
//
// - Orthographic camera, view height kViewHeight world units, looking at the origin,
//   so a distance is exact: a tile spans `tile_pixels` pixels across (along u).
// - Flat patch: the built-in plane in xy, tilted away from the camera by `tilt`
//   about x (the camera moves towards −y), sized to fill the frame at that tilt
//   (1/cos(tilt) longer along v), with repeats so one tile is
//   tile_pixels · kViewHeight / height world units on both axes (no stretch).
// - Curved: the built-in shape, radius kCurvedRadius, seen from −y; repeats so a
//   tile at the centre of the view spans `tile_pixels` pixels.
//
// - Variants: more flat patches of every fabric at the variant's tilts and distances,
//   under the variant's lights where it gives them (e.g. lit from the side away from
//   the camera), else the template's.
//
// Scene names are "<fabric>.flat<tilt>.<distance>", "<fabric>.<shape>.<distance>" and
// "<fabric>.flat<tilt>.<distance>.<variant>".

#include <filesystem>
#include <string>
#include <vector>

#include "loom/v1/scene.pb.h"

namespace loom::lab {

struct BenchScene {
  std::string name;
  std::string fabric;    // the fabric's name in the set
  std::string view;      // "flat0", "flat60", "sphere", ...
  std::string distance;  // "near", "mid", "far"
  double tile_pixels = 0.0;
  v1::SceneSpec scene;   // as a spec file would give it (defaults not applied)
  std::string variant;   // empty for the set's plain scenes
};

inline constexpr double kViewHeight = 2.0;
inline constexpr double kCurvedRadius = 0.8;

// Reads the set file (fabric paths relative to it) and expands it. Errors name the
// file and field (Error(kInvalidArgument)), or the missing fabric file (kNotFound).
std::vector<BenchScene> LoadBenchScenes(const std::filesystem::path& set_file);

}  // namespace loom::lab
