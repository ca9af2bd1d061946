// Stability on broken UV parameterisations (issue 7): cloth whose UV map squashes
// a band of triangles to zero UV area. Mesh preparation keeps them with a fallback
// tangent (core/scene/mesh_preparation.h); both renderers must draw them without a
// NaN. Figures and bounds: docs/stability.md.

#include <gtest/gtest.h>

#include <string>

#include "core/scene/scene_geometry.h"
#include "tests/core/render/comparison_scene.h"
#include "tests/stability/stability_figures.h"

namespace loom::testing {
namespace {

constexpr int kGrid = 4;  // quads a side

// The unit square in xy (the built-in plane's placement), kGrid × kGrid quads. Its
// UVs are the plane's, except that vertex row 2 takes row 1's v, so the quads
// between rows 1 and 2 have zero UV area (2·kGrid triangles), and the quad in the
// last row and column has all four UVs equal (2 more).
std::string SquashedUvPlaneObj() {
  std::string obj;
  const auto index = [](int i, int j) { return j * (kGrid + 1) + i + 1; };
  for (int j = 0; j <= kGrid; ++j) {
    for (int i = 0; i <= kGrid; ++i) {
      const float x = static_cast<float>(i) / kGrid, y = static_cast<float>(j) / kGrid;
      float u = x, v = (j == 2 ? 1.0f : static_cast<float>(j)) / kGrid;
      if (i >= kGrid - 1 && j >= kGrid - 1) u = v = 0.9f;
      obj += "v " + std::to_string(x - 0.5f) + " " + std::to_string(y - 0.5f) + " 0\n";
      obj += "vt " + std::to_string(u) + " " + std::to_string(v) + "\n";
    }
  }
  obj += "vn 0 0 1\n";
  for (int j = 0; j < kGrid; ++j) {
    for (int i = 0; i < kGrid; ++i) {
      const auto corner = [&](int di, int dj) {
        const std::string k = std::to_string(index(i + di, j + dj));
        return " " + k + "/" + k + "/1";
      };
      obj += "f" + corner(0, 0) + corner(1, 0) + corner(1, 1) + "\n";
      obj += "f" + corner(0, 0) + corner(1, 1) + corner(0, 1) + "\n";
    }
  }
  return obj;
}

TEST(StabilityMesh, ZeroAreaUvTrianglesRenderWithoutNaN) {
  ComparisonOptions options;
  options.mesh = R"({"obj_path": "squashed_uv_plane.obj"})";
  const v1::SceneSpec scene = MakeComparisonScene(options);
  const std::string obj = SquashedUvPlaneObj();
  const MeshTextResolver resolve = [&](const v1::MeshRef&, const TextSink& consume) { consume(obj); };

  const std::vector<SceneMesh> meshes = BuildSceneGeometry(scene, resolve);
  Figure("zero_area_uv", "mesh", "zero_area_uv_triangles", static_cast<double>(meshes[0].report.zero_area_uv_triangles),
         AtLeast(2 * kGrid + 2));
  Figure("zero_area_uv", "mesh", "dropped_triangles", static_cast<double>(meshes[0].report.dropped_degenerate_triangles),
         AtMost(0));
  // The squashed band shows the fabric stretched to a line in both methods, each
  // its own way; only the frame's mean is compared.
  CompareMethods("zero_area_uv", RenderSvbrdf(scene, resolve), RenderReference(scene, resolve),
                 {AtLeast(12.0), AtMost(0.15)});
}

// The bench's NaN case (the sweep, level_mode none over the sphere in frames
// panned by 0.55 and 1.1 px): a plain weave on the built-in sphere, level 0 alone,
// seen from 45° so the north pole, the uv seam and the silhouette are in the
// frame, under sub-pixel pans. The fit is a sparse one (4×4 views and lights, two
// lobes), where the fit without its lobe-peak guard placed spikes of 10^223
// between the sampled directions (the sweep's NaN came from such a spike
// overflowing in the shader); the asset's peaks stay bounded and the frames finite.
TEST(StabilityMesh, SphereAtLevelZeroUnderSubPixelPansStaysFinite) {
  ComparisonOptions options;
  options.fabric = R"({"woven": {"pattern": "WEAVE_PATTERN_PLAIN", "gap_ratio": 0.1}})";
  options.mesh = R"({"builtin": "BUILTIN_SHAPE_SPHERE"})";
  options.plane_width = options.plane_length = 0.8f;  // x and y; z keeps 1
  options.view_height = 2.4f;
  options.repeat = 15;
  options.level_mode = "LEVEL_MODE_NONE";
  options.precompute = R"({"spatial_resolution": 16, "view_directions": 16, "light_directions": 16, "lobes": 2})";
  const v1::SceneSpec scene = MakeComparisonScene(options);
  CheckFit("sphere_level0_pans", FitOf(scene.objects(0).fabric()), Unbounded());
  size_t non_finite = 0;
  for (const double pixels : {0.0, 0.55, 1.1}) {
    ComparisonOptions panned = options;
    panned.camera_shift = static_cast<float>(pixels * options.view_height / options.size);
    non_finite += NonFiniteCount(RenderSvbrdf(MakeComparisonScene(panned)));
  }
  Figure("sphere_level0_pans", "svbrdf", "frame_nonfinite", static_cast<double>(non_finite), AtMost(0));
}

}  // namespace
}  // namespace loom::testing
