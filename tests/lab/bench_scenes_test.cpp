#include "lab/bench_scenes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <glm/glm.hpp>
#include <set>

#include "core/scene/camera.h"
#include "core/scene/scene_geometry.h"
#include "core/spec/defaults.h"
#include "core/spec/validate.h"

namespace loom::lab {
namespace {

const std::filesystem::path kBenchSet = std::filesystem::path(LOOM_SOURCE_DIR) / "bench/scenes/bench_set.json";

// Pixel position of world point p (y down, as images are stored).
glm::dvec3 ToPixel(const v1::SceneSpec& scene, const glm::vec3& p) {
  const double width = scene.render().width(), height = scene.render().height();
  const CameraMatrices camera = MakeCameraMatrices(scene.camera(), static_cast<float>(width / height));
  const glm::vec4 view = camera.view * glm::vec4(p, 1.0f);
  const glm::vec4 clip = camera.projection * view;
  return {(clip.x / clip.w * 0.5 + 0.5) * width, (0.5 - clip.y / clip.w * 0.5) * height, -view.z};
}

TEST(BenchScenes, EveryFabricAtEveryTiltAndDistanceAndOnTheSphere) {
  const std::vector<BenchScene> scenes = LoadBenchScenes(kBenchSet);
  ASSERT_EQ(scenes.size(), 6u * (3 * 3 + 1));
  std::set<std::string> names, fabrics;
  for (const BenchScene& bench : scenes) {
    names.insert(bench.name);
    fabrics.insert(bench.fabric);
    ThrowIfAny(Validate(WithDefaults(bench.scene)));  // each is a valid plain scene spec
  }
  EXPECT_EQ(names.size(), scenes.size());
  EXPECT_EQ(fabrics, (std::set<std::string>{"stockinette", "rib2x2", "twocolour", "plain", "twill31", "satin5"}));
}

TEST(BenchScenes, ATileSpansTheStatedPixelsAndThePatchFillsTheFrame) {
  for (const BenchScene& bench : LoadBenchScenes(kBenchSet)) {
    if (bench.view.rfind("flat", 0) != 0) continue;
    SCOPED_TRACE(bench.name);
    const v1::SceneSpec scene = WithDefaults(bench.scene);
    const v1::SceneObject& cloth = scene.objects(0);
    const double tile_u = cloth.transform().scale().x() / cloth.fabric().repeat_u();
    const double tile_v = cloth.transform().scale().y() / cloth.fabric().repeat_v();
    EXPECT_NEAR(tile_u, tile_v, 1e-4 * tile_u);  // square tiles: the fabric is not stretched
    // The plane's centre row: one tile along u spans tile_pixels.
    const glm::dvec3 a = ToPixel(scene, {0, 0, 0}), b = ToPixel(scene, {static_cast<float>(tile_u), 0, 0});
    EXPECT_NEAR(glm::length(glm::dvec2(b - a)), bench.tile_pixels, 1e-3 * bench.tile_pixels);
    // Every corner of the patch lies outside the frame and in front of the camera.
    const auto meshes = BuildSceneGeometry(scene, FileMeshResolver({}));
    const Bounds bounds = SceneGeometryBounds(meshes);
    for (const float x : {bounds.low.x, bounds.high.x}) {
      for (const float y : {bounds.low.y, bounds.high.y}) {
        const glm::dvec3 corner = ToPixel(scene, {x, y, 0});
        EXPECT_GT(corner.z, scene.camera().near());
        EXPECT_TRUE(corner.x <= 0 || corner.x >= scene.render().width() || corner.y <= 0 ||
                    corner.y >= scene.render().height());
      }
    }
    const glm::dvec3 near_corner = ToPixel(scene, {bounds.low.x, bounds.low.y, 0});
    const glm::dvec3 far_corner = ToPixel(scene, {bounds.high.x, bounds.high.y, 0});
    EXPECT_LT(std::min(near_corner.x, far_corner.x), 0.0);
    EXPECT_GT(std::max(near_corner.x, far_corner.x), scene.render().width());
    EXPECT_LT(std::min(near_corner.y, far_corner.y), 0.0);
    EXPECT_GT(std::max(near_corner.y, far_corner.y), scene.render().height());
  }
}

}  // namespace
}  // namespace loom::lab
