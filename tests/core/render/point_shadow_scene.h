#pragma once
// A sphere over a plane, lit by a shadow-casting point light beside it, and where the
// sphere's shadow falls by ray geometry: what the GPU renderer's and the reference's
// point-light shadows are held to. The shadow crosses two of the light's cube faces
// (−z and +x, at x = 0.5), so a seam between shadow map faces shows too.

#include <functional>
#include <string>

#include "core/image/image.h"

namespace loom::testing {

// The scene (SceneSpec JSON), 64 × 64 pixels straight down on the 2 × 2 plane;
// `method` a RenderMethod name.
std::string PointShadowSceneJson(bool casts_shadows, const std::string& method);

struct PointShadowCheck {
  int inside = 0, outside = 0;      // pixels surely in the shadow, surely out of it
  int inside_plus_x_face = 0;       // of the inside ones, those the light's +x face sees
  int dark_inside = 0;              // inside ones with red below 1e-4 (no ambient)
  double worst_outside = 0.0;       // outside: largest |red − Lambert's| / Lambert's
};

// Classifies the plane's pixels by the distance from the sphere's centre to the
// segment from the plane point to the light, away from the shadow's edge (the sphere
// is a mesh; the maps are filtered) and from the sphere itself, and measures them.
PointShadowCheck CheckPointShadow(const Image& image);

// Renders the scene with and without casts_shadows through `render` (the scene's JSON
// → its frame) and expects: with, every pixel surely inside the shadow black (on both
// faces), every one surely outside within `lit_tolerance` of Lambert's; without, no
// pixel inside black.
void ExpectShadowWhereTheRaysMeetTheSphere(const std::function<Image(const std::string& json)>& render,
                                           const std::string& method, double lit_tolerance);

}  // namespace loom::testing
