// Stability at the ends of the screen footprint (issue 7): a tile far below a pixel
// (extreme minification, and the repeat count at its cap), and a texel spanning
// many pixels (magnification, close up). Figures and bounds: docs/stability.md.

#include <gtest/gtest.h>

#include <vector>

#include "core/metrics/image_metrics.h"
#include "core/spec/limits.h"
#include "tests/core/render/comparison_scene.h"
#include "tests/stability/stability_figures.h"

namespace loom::testing {
namespace {

// 1024 tiles over the 2-unit plane in a 96-px, 1-unit view: a tile spans 0.19 px.
// The coarsest fitted level (one texel, the tile's mean) must carry the frame:
// its mean radiance is the reference's, and a one-pixel camera move does not
// flicker. Level 0 alone (LEVEL_MODE_NONE) picks one of ~84 texels across a pixel and
// flickers: documented as the failure the fitted levels exist to prevent. The mean
// is bounded as the baseline's (±10%): the one-texel level fitted from its own
// samples (asset format 5) is 8.6% too bright here against 3.0% when it started
// from its children's fits, with the same error on its samples (RMSE 0.0434
// against 0.0431): 45° lies between the 36-direction set's view rings at 41° and
// 72°, where no stored view constrains the lobes (docs/accuracy.md "Mean radiance
// against the view angle").
TEST(StabilityFootprint, ExtremeMinificationTileFarBelowAPixel) {
  ComparisonOptions options;
  options.repeat = 1024;
  const v1::SceneSpec scene = MakeComparisonScene(options);
  CompareMethods("minification_0.19px", RenderSvbrdf(scene), RenderReference(scene),
                 {AtLeast(19.0), AtMost(0.10)});
  const auto flicker = [&](const char* level_mode) {
    std::vector<Image> frames;
    for (int k = 0; k < 3; ++k) {
      ComparisonOptions moved = options;
      moved.perspective = true;
      moved.level_mode = level_mode;
      moved.camera_shift = static_cast<float>(k) / options.size;  // one pixel
      frames.push_back(RenderSvbrdf(MakeComparisonScene(moved)));
    }
    return TemporalFlicker(frames, -1, 0);
  };
  Figure("minification_0.19px", "svbrdf", "flicker", flicker("LEVEL_MODE_TRILINEAR"), AtMost(0.002));
  Figure("minification_0.19px", "svbrdf_level0", "flicker", flicker("LEVEL_MODE_NONE"), Unbounded());
}

// The repeat count at its cap (kMaxRepeat tiles across the plane: 0.05 px a tile):
// the tile coordinate reaches 4096, where a float keeps 2^-12 of a tile, still
// finer than a 16-texel tile's texels.
TEST(StabilityFootprint, RepeatCountAtTheCap) {
  ComparisonOptions options;
  options.repeat = kMaxRepeat;
  const v1::SceneSpec scene = MakeComparisonScene(options);
  CompareMethods("repeat_at_cap_4096", RenderSvbrdf(scene), RenderReference(scene), {AtLeast(19.0), AtMost(0.10)});
}

// Close up in perspective at 45°: two tiles over the plane and a 0.25-unit view,
// so a tile spans ~380 px and a level-0 texel ~24 px. The reference shows one
// yarn's round silhouette and the shadowed gap beside it; svbrdf shows one BRDF
// per texel, blended bilinearly into its neighbours over the 24 px. This is
// outside the method's range (a fitted texel is meant to cover about a pixel):
// measured 8.9 dB, mean radiance 0.64 of the reference's (nearest texels: 8.6 dB,
// 24-px blocks); the bounds only keep it from getting worse.
TEST(StabilityFootprint, MagnificationATexelSpansManyPixels) {
  ComparisonOptions options;
  options.repeat = 2;
  options.view_height = 0.25f;
  options.perspective = true;
  const v1::SceneSpec scene = MakeComparisonScene(options);
  CompareMethods("magnification_24px_texel", RenderSvbrdf(scene), RenderReference(scene),
                 {AtLeast(7.5), AtMost(0.45)});
}

}  // namespace
}  // namespace loom::testing
