#include "lab/bench_scenes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <glm/glm.hpp>
#include <numbers>
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

TEST(BenchScenes, EveryFabricAtEveryTiltAndDistanceOnTheSphereAndInEachVariant) {
  const std::vector<BenchScene> scenes = LoadBenchScenes(kBenchSet);
  // 3 tilts × 3 distances, the sphere, opposite-lit 2 tilts × 2 distances, close-ups at 2 tilts.
  ASSERT_EQ(scenes.size(), 6u * (3 * 3 + 1 + 2 * 2 + 2));
  std::set<std::string> names, fabrics;
  for (const BenchScene& bench : scenes) {
    names.insert(bench.name);
    fabrics.insert(bench.fabric);
    ThrowIfAny(Validate(WithDefaults(bench.scene)));  // each is a valid plain scene spec
  }
  EXPECT_EQ(names.size(), scenes.size());
  EXPECT_EQ(fabrics, (std::set<std::string>{"stockinette", "rib2x2", "twocolour", "plain", "twill31", "satin5"}));
}

// Opposite-lit: the light comes from the side of the patch away from the camera
// (the camera stands at −y of a tilted patch), 48° from the normal; close-ups: a
// tile 128 pixels across, under the template's light.
TEST(BenchScenes, VariantsChangeTheLightOrTheDistanceOnly) {
  const std::vector<BenchScene> scenes = LoadBenchScenes(kBenchSet);
  int opposite = 0, closeups = 0;
  for (const BenchScene& bench : scenes) {
    if (bench.variant == "opposite") {
      ++opposite;
      ASSERT_EQ(bench.scene.lights_size(), 1);
      const v1::Vec3& d = bench.scene.lights(0).direction();
      EXPECT_GT(d.y(), 0.0f) << bench.name;
      EXPECT_LT(bench.scene.camera().position().y(), 0.0f) << bench.name;
      EXPECT_NEAR(std::atan2(std::hypot(d.x(), d.y()), d.z()) * 180.0 / std::numbers::pi, 48.0, 0.1);
      EXPECT_EQ(bench.name, bench.fabric + "." + bench.view + "." + bench.distance + ".opposite");
    } else if (bench.variant == "closeup") {
      ++closeups;
      EXPECT_EQ(bench.tile_pixels, 128.0);
      EXPECT_LT(bench.scene.lights(0).direction().y(), 0.0f) << bench.name;  // the template's light
    }
  }
  EXPECT_EQ(opposite, 6 * 4);
  EXPECT_EQ(closeups, 6 * 2);
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
