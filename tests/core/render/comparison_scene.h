#pragma once
// One fabric on a plane, rendered by both methods: the scene the svbrdf-vs-reference
// tests and the stability suite (tests/stability/) compare. The fabric is precomputed
// with small settings (once per process) so each test stays quick.

#include <string>

#include "core/fit/fabric_fit.h"
#include "core/image/image.h"
#include "core/scene/scene_geometry.h"
#include "loom/v1/scene.pb.h"

namespace loom::testing {

// 16² texels, 6×6 views and lights, one lobe: about 4 s on two cores.
inline constexpr const char* kSmallSettings =
    R"({"spatial_resolution": 16, "view_directions": 36, "light_directions": 36, "lobes": 1})";
inline constexpr const char* kKnit = R"({"knit": {}})";
inline constexpr const char* kLooseWeave = R"({"woven": {"pattern": "WEAVE_PATTERN_PLAIN", "gap_ratio": 0.4}})";

struct ComparisonOptions {
  std::string fabric = kKnit;              // FabricSpec JSON
  std::string precompute = kSmallSettings;  // PrecomputeSettings JSON
  // Built-in plane scaled to plane_width (x) × plane_length (y); `mesh` replaces
  // the built-in (MeshRef JSON) and keeps the scale.
  std::string mesh = R"({"builtin": "BUILTIN_SHAPE_PLANE"})";
  float plane_width = 2;
  float plane_length = 2;
  float repeat = 12;         // tiles across the plane's width; along its length at the same density
  float tilt_degrees = 45;   // camera elevation from the zenith, looking along +y
  float camera_shift = 0;    // world units along x
  float view_height = 1;     // world units the frame spans at the target
  bool perspective = false;  // same view height at the target as the orthographic view
  bool red_floor = false;    // a red plane under the cloth, seen through its holes
  bool shadows = false;      // the light casts shadows (cloth's onto the floor)
  std::string light = R"({"x": -0.3, "y": -0.5, "z": 1})";  // towards the light (Vec3 JSON)
  int size = 96;             // pixels a side
  int reference_samples = 64;
  const char* level_mode = "LEVEL_MODE_TRILINEAR";
  const char* texel_filter = "TEXEL_FILTER_UNSPECIFIED";  // the renderer's default: bilinear
};

// The scene, defaults applied and validated. The camera stands far enough back
// that the whole plane lies in front of it at any tilt.
v1::SceneSpec MakeComparisonScene(const ComparisonOptions& options);

// The fit of a binding, precomputed on first use and kept for the process.
const FittedFabric& FitOf(const v1::FabricBinding& binding);

// Meshes from `resolve` (obj_path meshes); built-ins need none.
Image RenderSvbrdf(const v1::SceneSpec& scene, const MeshTextResolver& resolve = FileMeshResolver("."));
Image RenderReference(const v1::SceneSpec& scene, const MeshTextResolver& resolve = FileMeshResolver("."));

double MeanRed(const Image& image);

}  // namespace loom::testing
