// The lumislice renderer (core/render/lumislice_renderer.h) on llvmpipe: the frame does
// not depend on the order segments arrive in, plain objects hide the yarn behind them,
// a close-up agrees with the reference's march through the same yarn volume, and far
// away a pixel holds the mean of what a finer frame sees in it.

#include "core/render/lumislice_renderer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "core/gl/egl_context.h"
#include "core/metrics/image_metrics.h"
#include "core/render/reference_renderer.h"
#include "core/spec/defaults.h"
#include "core/spec/spec_json.h"
#include "core/spec/validate.h"

namespace loom {
namespace {

// A two-ply, slightly fuzzy red stockinette on the 1 × 1 plane, `repeat` tiles a side,
// seen from above and the side, lit from the side; optionally a grey board hovering
// over the plane's left half.
std::string KnitScene(int size, int repeat, bool board, const std::string& method) {
  const std::string cloth = R"({"mesh": {"builtin": "BUILTIN_SHAPE_PLANE"}, "fabric": {"fabric":
      {"knit": {"pattern": "KNIT_PATTERN_STOCKINETTE", "wales": 2, "courses": 2},
       "yarns": [{"radius": 0.07, "plies": 2, "twist_degrees": 25, "fuzz": 0.2, "roughness": 0.6,
                  "diffuse_albedo": {"r": 0.62, "g": 0.08, "b": 0.07}, "specular_albedo": {"r": 0.04, "g": 0.04, "b": 0.04}}]},
      "repeat_u": )" + std::to_string(repeat) + R"(, "repeat_v": )" + std::to_string(repeat) + "}}";
  const std::string over = board ? R"(, {"mesh": {"builtin": "BUILTIN_SHAPE_PLANE"}, "base_colour": {"r": 0.5, "g": 0.5, "b": 0.5},
      "transform": {"translation": {"x": -0.3, "z": 0.2}, "scale": {"x": 0.4, "y": 1.2, "z": 1}}})"
                                 : "";
  const std::string side = std::to_string(size);
  return R"({"objects": [)" + cloth + over + R"(],
    "camera": {"position": {"x": 0.1, "y": -0.6, "z": 1.1}, "target": {"x": 0, "y": 0, "z": 0}, "fov_y_degrees": 40},
    "lights": [{"direction": {"x": -0.4, "y": -0.6, "z": 1}, "intensity": 3}],
    "ambient": {"r": 0.05, "g": 0.05, "b": 0.06}, "background": {"r": 0.02, "g": 0.025, "b": 0.03},
    "render": {"method": ")" + method + R"(", "width": )" + side + R"(, "height": )" + side + R"(, "reference_samples": 16}})";
}

struct Prepared {
  v1::SceneSpec scene;
  std::vector<SceneMesh> meshes;
  YarnLumislices lumislices;
  std::vector<const YarnLumislices*> yarns;
};

Prepared Prepare(const std::string& json) {
  Prepared prepared;
  prepared.scene = WithDefaults(ParseSpecJson<v1::SceneSpec>(json, "scene"));
  ValidateOrThrow(prepared.scene);
  prepared.meshes = BuildSceneGeometry(prepared.scene, FileMeshResolver("."));
  prepared.lumislices =
      BuildFabricLumislices(WithDefaults(prepared.scene.objects(0).fabric().fabric()), LumisliceSettings());
  prepared.yarns.assign(prepared.meshes.size(), nullptr);
  prepared.yarns[0] = &prepared.lumislices;
  return prepared;
}

LumisliceRenderer& Renderer() {
  static const auto context = gl::EglContext::Create();
  static LumisliceRenderer renderer(*context);
  return renderer;
}

double MaxDifference(const Image& a, const Image& b) {
  double most = 0.0;
  for (size_t i = 0; i < a.pixels.size(); ++i) most = std::max(most, std::abs(double(a.pixels[i]) - b.pixels[i]));
  return most;
}

// Segments are blended back to front whatever order they are handed in.
TEST(LumisliceRenderer, SlicesInAnySubmissionOrderGiveTheSameFrame) {
  const Prepared p = Prepare(KnitScene(64, 3, false, "RENDER_METHOD_LUMISLICE"));
  const LumisliceFrame in_order = Renderer().Render(p.scene, p.meshes, p.yarns);
  ASSERT_GT(in_order.segments, 500u);
  int yarn_pixels = 0;
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 64; ++x) yarn_pixels += in_order.rendered.image.at(x, y, 0) > 0.1f ? 1 : 0;
  }
  EXPECT_GT(yarn_pixels, 64 * 64 / 8);
  for (const uint64_t seed : {1u, 2u, 99u}) {
    const LumisliceFrame shuffled = Renderer().Render(p.scene, p.meshes, p.yarns, seed);
    EXPECT_EQ(MaxDifference(shuffled.rendered.image, in_order.rendered.image), 0.0) << "seed " << seed;
  }
}

// A plain object in front of the cloth hides it: where the board is, the frame is the
// board's, as without the yarn behind it.
TEST(LumisliceRenderer, PlainObjectsInFrontHideTheYarn) {
  const Prepared with_board = Prepare(KnitScene(64, 3, true, "RENDER_METHOD_LUMISLICE"));
  const Image frame = Renderer().Render(with_board.scene, with_board.meshes, with_board.yarns).rendered.image;
  std::vector<SceneMesh> board_only;
  board_only.push_back(with_board.meshes[1]);
  const Image board = Renderer().Render(with_board.scene, board_only, {nullptr}).rendered.image;
  int covered = 0;
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 64; ++x) {
      if (std::abs(board.at(x, y, 0) - 0.02f) < 1e-3f) continue;  // background: the board is not here
      ++covered;
      for (int c = 0; c < 3; ++c) ASSERT_NEAR(frame.at(x, y, c), board.at(x, y, c), 1e-5f) << x << ", " << y;
    }
  }
  EXPECT_GT(covered, 300);
}

// The same yarn volume, marched by the reference (16 samples a pixel): a close-up of the
// plied, fuzzy knit agrees to within what the lumislice approximates (straight yarn
// around each voxel for the light, a level's voxels). It is a little darker: the table's
// fibre walks stay in the voxel's yarn, the reference's go on into the yarns around it.
TEST(LumisliceRenderer, CloseUpAgreesWithTheVolumeReference) {
  const Prepared p = Prepare(KnitScene(96, 3, false, "RENDER_METHOD_LUMISLICE"));
  const Image lumislice = Renderer().Render(p.scene, p.meshes, p.yarns).rendered.image;
  v1::SceneSpec reference_scene = p.scene;
  reference_scene.mutable_render()->set_method(v1::RENDER_METHOD_REFERENCE);
  const Image reference = ReferenceRenderer(2).Render(reference_scene, p.meshes).image;
  const ImageComparison comparison = CompareImages(lumislice, reference);
  EXPECT_GT(comparison.psnr_db, 19.0);
  EXPECT_NEAR(comparison.mean_ratio, 0.92, 0.05);
}

// Far away the yarn is narrower than a pixel: drawn a pixel wide with its opacity scaled
// by its coverage, a pixel holds about what the frame 8× finer, where the yarn is
// several pixels wide, averages over it (one ray through the true width: 8 dB; without
// the coverage: 1.6× as bright), from merged segments, far fewer than the skeleton's.
// Darker by up to a quarter at this slant: widened yarns that lie side by side let the
// ones behind show through (docs/lumislice.md).
TEST(LumisliceRenderer, SubPixelYarnGivesTheFinerFramesPixelMean) {
  constexpr int kSide = 48, kFactor = 8;
  const Prepared coarse = Prepare(KnitScene(kSide, 24, false, "RENDER_METHOD_LUMISLICE"));
  const LumisliceFrame far = Renderer().Render(coarse.scene, coarse.meshes, coarse.yarns);
  const Prepared fine = Prepare(KnitScene(kSide * kFactor, 24, false, "RENDER_METHOD_LUMISLICE"));
  const LumisliceFrame near = Renderer().Render(fine.scene, fine.meshes, fine.yarns);
  EXPECT_LT(far.segments * 2, near.segments);
  const ImageComparison comparison = CompareImages(far.rendered.image, BoxDownsampled(near.rendered.image, kFactor));
  EXPECT_GT(comparison.psnr_db, 15.0);
  EXPECT_NEAR(comparison.mean_ratio, 0.85, 0.15);
}

// A cache builds each knit fabric's lumislices once and hands the same ones back, until
// more fabrics than it holds push the least recently used out.
TEST(LumisliceRenderer, ACacheBuildsEachFabricOnce) {
  const Prepared first = Prepare(KnitScene(16, 1, false, "RENDER_METHOD_LUMISLICE"));
  v1::SceneSpec other_scene = first.scene;
  other_scene.mutable_objects(0)->mutable_fabric()->mutable_fabric()->mutable_yarns(0)->mutable_diffuse_albedo()->set_g(
      0.5f);
  const std::vector<SceneMesh> other = BuildSceneGeometry(other_scene, FileMeshResolver("."));
  LumisliceSettings settings;
  settings.resolution = 8;
  for (const size_t capacity : {1u, 2u}) {
    LumisliceCache cache(capacity);
    const SceneLumislices a = BuildSceneLumislices(first.meshes, settings, &cache);
    const SceneLumislices again = BuildSceneLumislices(first.meshes, settings, &cache);
    EXPECT_EQ(a.built, 1u);
    EXPECT_EQ(again.built, 0u);
    EXPECT_EQ(again.per_mesh[0], a.per_mesh[0]);
    EXPECT_EQ(BuildSceneLumislices(other, settings, &cache).built, 1u);
    EXPECT_EQ(BuildSceneLumislices(first.meshes, settings, &cache).built, capacity == 1 ? 1u : 0u) << capacity;
  }
  EXPECT_EQ(BuildSceneLumislices(first.meshes, settings).built, 1u);  // without a cache
}

// The yarn shadows what it stands over (eq. 10 in the shadow map's light view): a board
// 0.3 under the knit, lit at a slant, is darker where the knit's shadow falls beside it,
// and where the shadow does not fall it is the board's own frame. A directional light,
// and a point light whose shadow falls about as far (its cube face's perspective view).
class YarnShadowOnPlainObjects : public ::testing::TestWithParam<const char*> {};

TEST_P(YarnShadowOnPlainObjects, TheYarnShadowsPlainObjectsUnderIt) {
  const std::string json = R"({"objects": [
      {"mesh": {"builtin": "BUILTIN_SHAPE_PLANE"}, "fabric": {"fabric":
        {"knit": {"pattern": "KNIT_PATTERN_STOCKINETTE", "wales": 2, "courses": 2},
         "yarns": [{"radius": 0.07, "plies": 2, "twist_degrees": 25, "fuzz": 0.2, "roughness": 0.6,
                    "diffuse_albedo": {"r": 0.62, "g": 0.08, "b": 0.07}}]}, "repeat_u": 3, "repeat_v": 3}},
      {"mesh": {"builtin": "BUILTIN_SHAPE_PLANE"}, "base_colour": {"r": 0.5, "g": 0.5, "b": 0.5},
       "transform": {"translation": {"z": -0.3}, "scale": {"x": 3, "y": 3, "z": 1}}}],
    "camera": {"projection": "PROJECTION_ORTHOGRAPHIC", "ortho_height": 3, "position": {"z": 3}, "target": {},
               "up": {"y": 1}},
    "lights": [)" + std::string(GetParam()) + R"(],
    "ambient": {"r": 0.05, "g": 0.05, "b": 0.05}, "background": {"r": 0, "g": 0, "b": 0},
    "render": {"method": "RENDER_METHOD_LUMISLICE", "width": 96, "height": 96}})";
  const Prepared p = Prepare(json);
  const Image frame = Renderer().Render(p.scene, p.meshes, p.yarns).rendered.image;
  std::vector<SceneMesh> board_only;
  board_only.push_back(p.meshes[1]);
  const Image board = Renderer().Render(p.scene, board_only, {nullptr}).rendered.image;
  // The mean of x ∈ [x0, x1], y ∈ [−0.3, 0.3] on the board (the cloth spans ±0.5; its
  // shadow falls 0.18 to 0.21 further along x).
  const auto mean = [](const Image& image, float x0, float x1) {
    double sum = 0.0;
    int count = 0;
    for (int py = 0; py < 96; ++py) {
      for (int px = 0; px < 96; ++px) {
        const float x = (px + 0.5f) / 96.0f * 3.0f - 1.5f, y = 1.5f - (py + 0.5f) / 96.0f * 3.0f;
        if (x < x0 || x > x1 || std::abs(y) > 0.3f) continue;
        sum += image.at(px, py, 1);
        ++count;
      }
    }
    return sum / count;
  };
  const double beyond = mean(board, 0.85f, 1.2f);
  EXPECT_NEAR(mean(frame, 0.85f, 1.2f), beyond, 1e-3 * beyond);  // beyond the shadow: the board's own
  const double shadowed = mean(frame, 0.55f, 0.65f) / mean(board, 0.55f, 0.65f);
  EXPECT_LT(shadowed, 0.7) << shadowed;
  EXPECT_GT(shadowed, 0.05) << shadowed;
}

INSTANTIATE_TEST_SUITE_P(
    Lights, YarnShadowOnPlainObjects,
    ::testing::Values(R"({"direction": {"x": -0.6, "y": 0, "z": 1}, "intensity": 3, "casts_shadows": true})",
                      R"({"type": "LIGHT_TYPE_POINT", "position": {"x": -3, "y": 0, "z": 5}, "intensity": 100,
                          "casts_shadows": true})"),
    [](const ::testing::TestParamInfo<const char*>& info) { return info.index == 0 ? "Directional" : "Point"; });

// render.msaa_samples 4: 2 × 2 rays a pixel, the same as the frame twice as large
// averaged, and closer to the reference's 16 samples a pixel than one ray.
TEST(LumisliceRenderer, RaysAPixelAverageTheLargerFrame) {
  Prepared p = Prepare(KnitScene(48, 3, false, "RENDER_METHOD_LUMISLICE"));
  const Image one_ray = Renderer().Render(p.scene, p.meshes, p.yarns).rendered.image;
  p.scene.mutable_render()->set_msaa_samples(4);
  const Image four_rays = Renderer().Render(p.scene, p.meshes, p.yarns).rendered.image;
  const Prepared large = Prepare(KnitScene(96, 3, false, "RENDER_METHOD_LUMISLICE"));
  const Image averaged = BoxDownsampled(Renderer().Render(large.scene, large.meshes, large.yarns).rendered.image, 2);
  EXPECT_LT(MaxDifference(four_rays, averaged), 1e-6);
  v1::SceneSpec reference_scene = p.scene;
  reference_scene.mutable_render()->set_method(v1::RENDER_METHOD_REFERENCE);
  const Image reference = ReferenceRenderer(2).Render(reference_scene, p.meshes).image;
  EXPECT_GT(CompareImages(four_rays, reference).psnr_db, CompareImages(one_ray, reference).psnr_db + 0.5);
}

}  // namespace
}  // namespace loom
