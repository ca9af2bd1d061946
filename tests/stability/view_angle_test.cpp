// Stability at grazing views (issue 7): the standard knit seen from 80° to 89° off
// the normal, and a loose weave's holes at 85°. Figures and bounds: docs/stability.md.

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "tests/core/render/comparison_scene.h"
#include "tests/core/render/image_probes.h"
#include "tests/stability/stability_figures.h"

namespace loom::testing {
namespace {

// The plane is long enough to fill the 1-unit-high view at `tilt` degrees.
ComparisonOptions GrazingView(float tilt) {
  ComparisonOptions options;
  options.tilt_degrees = tilt;
  options.plane_length = std::ceil(1.2f / std::cos(tilt * 3.14159265f / 180.0f));
  return options;
}

// Seen at grazing, a pixel covers many tiles along the view (a tile is 16 px across
// but 16·cos θ px along it: 2.8 px at 80°, 0.28 px at 89°) and the reference's
// yarns hide each other. svbrdf holds T(v) at the outermost stored ring of views
// (72° on a 6×6 grid) and its lobes extrapolate beyond it, so it comes out darker
// the closer the view is to the horizon: measured mean radiance 0.96, 0.82 and
// 0.76 of the reference's at 80°, 85° and 89° (0.85, 0.68 and 0.57 while alpha was
// held at the 72° ring's value, letting the black background through). Its one
// isotropic level also point-samples the footprint's long axis (moiré across the
// wales), but averaging 4×4 samples a pixel gains at most 1.2 dB: the error is
// the model's (docs/stability.md).
TEST(StabilityGrazing, KnitFromEightyToEightyNineDegrees) {
  struct Case {
    float tilt;
    ComparisonBounds bounds;
  };
  for (const Case& c : {Case{80, {AtLeast(11.0), AtMost(0.15)}}, Case{85, {AtLeast(9.5), AtMost(0.3)}},
                        Case{89, {AtLeast(9.0), AtMost(0.4)}}}) {
    const std::string regime = "grazing_" + std::to_string(static_cast<int>(c.tilt)) + "deg";
    ComparisonOptions options = GrazingView(c.tilt);
    const v1::SceneSpec scene = MakeComparisonScene(options);
    const Image reference = RenderReference(scene);
    const double trilinear = CompareMethods(regime, RenderSvbrdf(scene), reference, c.bounds).psnr_db;
    // Anisotropic levels (LEVEL_MODE_ANISOTROPIC) shade up to 8 points along the
    // long axis: +0.7 dB at 80° and 85°, nothing at 89° (a footprint 57 times longer
    // than wide), a little darker; the same bounds hold.
    options.level_mode = "LEVEL_MODE_ANISOTROPIC";
    const double anisotropic = CompareMethods(regime, RenderSvbrdf(MakeComparisonScene(options)), reference,
                                              c.bounds, "svbrdf_anisotropic")
                                   .psnr_db;
    Figure(regime, "svbrdf_anisotropic", "psnr_gain_db", anisotropic - trilinear, Unbounded());
    // Nearest texels (TEXEL_FILTER_NEAREST, the paper's lookup) instead of the default
    // bilinear ones, trilinear levels: -0.2 dB at 80° and 85°, -0.1 at 89°; the same bounds.
    options.level_mode = "LEVEL_MODE_TRILINEAR";
    options.texel_filter = "TEXEL_FILTER_NEAREST";
    const double nearest = CompareMethods(regime, RenderSvbrdf(MakeComparisonScene(options)), reference, c.bounds,
                                          "svbrdf_nearest")
                               .psnr_db;
    Figure(regime, "svbrdf_nearest", "psnr_gain_db", nearest - trilinear, Unbounded());
  }
}

// A plain weave with 40% gaps over a red floor: head-on the floor shows through
// the holes; at 85° the yarns hide it in the reference (the gaps close up along the
// view). svbrdf's coverage is alpha(v) of the stored views, interpolated, and
// towards 1 at the horizon beyond the outermost ring (core/shaders/fabric_surface.glsl):
// red fraction 0.057 against the reference's 0.003 (0.097 with nearest texels);
// held at the 72° ring's alpha it was 0.33. The mean red is not compared: the floor is red.
TEST(StabilityGrazing, LooseWeaveHolesCloseAtEightyFiveDegrees) {
  ComparisonOptions options = GrazingView(85);
  options.fabric = kLooseWeave;
  options.repeat = 6;
  options.red_floor = true;
  const v1::SceneSpec scene = MakeComparisonScene(options);
  const Image svbrdf = RenderSvbrdf(scene), reference = RenderReference(scene);
  CompareMethods("holes_grazing_85deg", svbrdf, reference, {AtLeast(7.5), Unbounded()});
  const double red_svbrdf = RedFraction(svbrdf), red_reference = RedFraction(reference);
  Figure("holes_grazing_85deg", "reference", "red_fraction", red_reference, AtMost(0.05));
  Figure("holes_grazing_85deg", "svbrdf", "red_fraction", red_svbrdf, Unbounded());
  Figure("holes_grazing_85deg", "svbrdf", "red_fraction_excess", red_svbrdf - red_reference, AtMost(0.15));
  CheckFit("holes_grazing_85deg", FitOf(scene.objects(0).fabric()), AtMost(0.25));
}

}  // namespace
}  // namespace loom::testing
