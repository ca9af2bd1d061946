#include "core/spec/defaults.h"

#include <cmath>
#include <numeric>

namespace loom {
namespace {

// PrecomputeSettings.
constexpr uint32_t kDefaultSpatialResolution = 32;
constexpr uint32_t kDefaultDirections = 64;  // an 8×8 grid, views and lights alike
constexpr uint32_t kDefaultLobes = 2;
constexpr float kDefaultLutChangeThreshold = 0.1f;
constexpr uint32_t kDefaultMaxAlternations = 8;
constexpr uint32_t kDefaultMaxLmIterations = 50;
constexpr uint32_t kDefaultIndirectBounces = 1;
constexpr uint32_t kDefaultSupersampling = 2;  // 2×2 rays per texel
constexpr uint32_t kDefaultFactoredRank = 4;
constexpr uint32_t kDefaultNeuralChannels = 8;
constexpr uint32_t kDefaultNeuralHidden = 32;
constexpr uint32_t kDefaultNeuralSteps = 100000;
constexpr uint32_t kDefaultNeuralFrequencies = 2;
constexpr uint32_t kDefaultTableViewDirections = 81;  // 9×9, for the table methods
constexpr uint32_t kDefaultTableSpatialResolution = 64;

// FabricSpec. Yarn radii are fractions of the loop width (knit) or yarn pitch (woven).
constexpr float kDefaultKnitYarnRadius = 0.07f;
constexpr float kDefaultWovenYarnRadius = 0.25f;
constexpr uint32_t kDefaultPlies = 1;
constexpr float kDefaultRoughness = 0.5f;
constexpr float kDefaultHeightScale = 1.0f;   // microflake: the geometry's own frame
constexpr float kDefaultLambertBlend = 1.0f;  // microflake: Lambert about the ply normal
constexpr float kDefaultDiffuseTransmission = 0.0f;  // microflake: the diffuse part reflects
constexpr float kDefaultDiffuseAlbedo = 0.5f;
constexpr float kDefaultSpecularAlbedo = 0.04f;  // a dielectric fibre at normal incidence
constexpr uint32_t kDefaultRibWidth = 1;
constexpr float kDefaultLoopAspect = 1.25f;
constexpr uint32_t kDefaultTwillOver = 2;
constexpr uint32_t kDefaultTwillUnder = 1;
constexpr uint32_t kDefaultSatinRepeat = 5;
constexpr uint32_t kDefaultBasketGroup = 2;
constexpr float kDefaultInclinationDegrees = 20.0f;

// RenderSettings.
constexpr uint32_t kDefaultWidth = 960;
constexpr uint32_t kDefaultHeight = 540;
constexpr uint32_t kDefaultMsaaSamples = 4;
constexpr uint32_t kDefaultShadowMapSize = 2048;
constexpr uint32_t kDefaultReferenceSamples = 64;

// SceneSpec.
constexpr float kDefaultRepeat = 1.0f;
constexpr float kDefaultFovYDegrees = 40.0f;
constexpr float kDefaultOrthoHeight = 2.0f;
constexpr float kDefaultNear = 0.01f;
constexpr float kDefaultFar = 100.0f;
constexpr float kDefaultLightIntensity = 1.0f;
// Objects without a fabric are Lambertian in their base colour: a light grey.
constexpr float kDefaultBaseColour = 0.8f;

// AnimationSpec: the paper's frame rate.
constexpr float kDefaultFramesPerSecond = 25.0f;

void SetGrey(v1::Rgb* rgb, float value) {
  rgb->set_r(value);
  rgb->set_g(value);
  rgb->set_b(value);
}

bool IsZero(const v1::Vec3& v) { return v.x() == 0 && v.y() == 0 && v.z() == 0; }

void SetVec3(v1::Vec3* v, float x, float y, float z) {
  v->set_x(x);
  v->set_y(y);
  v->set_z(z);
}

void ApplyYarnDefaults(v1::YarnSpec& yarn, float default_radius) {
  if (yarn.radius() == 0) yarn.set_radius(default_radius);
  if (yarn.plies() == 0) yarn.set_plies(kDefaultPlies);
  if (yarn.roughness() == 0) yarn.set_roughness(kDefaultRoughness);
  if (!yarn.has_diffuse_albedo()) SetGrey(yarn.mutable_diffuse_albedo(), kDefaultDiffuseAlbedo);
  if (!yarn.has_specular_albedo()) SetGrey(yarn.mutable_specular_albedo(), kDefaultSpecularAlbedo);
  if (yarn.shading() == v1::YARN_SHADING_MICROFLAKE) {
    if (!yarn.has_height_scale()) yarn.set_height_scale(kDefaultHeightScale);
    if (!yarn.has_lambert_blend()) yarn.set_lambert_blend(kDefaultLambertBlend);
    if (!yarn.has_diffuse_transmission()) yarn.set_diffuse_transmission(kDefaultDiffuseTransmission);
  } else if (yarn.shading() == v1::YARN_SHADING_KAJIYA_KAY) {
    // Kajiya-Kay spelled out is Kajiya-Kay unset: one key, the one yarns had before
    // the field existed.
    yarn.clear_shading();
  }
}

void ApplyKnitDefaults(v1::KnitSpec& knit) {
  if (knit.pattern() == v1::KNIT_PATTERN_UNSPECIFIED) knit.set_pattern(v1::KNIT_PATTERN_STOCKINETTE);
  if (knit.pattern() == v1::KNIT_PATTERN_RIB) {
    if (knit.rib_knit() == 0) knit.set_rib_knit(kDefaultRibWidth);
    if (knit.rib_purl() == 0) knit.set_rib_purl(kDefaultRibWidth);
  }
  const KnitRepeat repeat = KnitPatternRepeat(knit);
  if (knit.wales() == 0) knit.set_wales(repeat.wales);
  if (knit.courses() == 0) knit.set_courses(repeat.courses);
  if (knit.loop_aspect() == 0) knit.set_loop_aspect(kDefaultLoopAspect);
}

void ApplyWovenDefaults(v1::WovenSpec& woven) {
  if (woven.pattern() == v1::WEAVE_PATTERN_UNSPECIFIED) woven.set_pattern(v1::WEAVE_PATTERN_PLAIN);
  switch (woven.pattern()) {
    case v1::WEAVE_PATTERN_TWILL:
      if (woven.n() == 0) woven.set_n(kDefaultTwillOver);
      if (woven.m() == 0) woven.set_m(kDefaultTwillUnder);
      break;
    case v1::WEAVE_PATTERN_SATIN:
      if (woven.n() == 0) woven.set_n(kDefaultSatinRepeat);
      if (woven.m() == 0) woven.set_m(SmallestSatinMove(woven.n()));
      break;
    case v1::WEAVE_PATTERN_BASKET:
      if (woven.n() == 0) woven.set_n(kDefaultBasketGroup);
      break;
    default: break;
  }
  if (woven.inclination_degrees() == 0) woven.set_inclination_degrees(kDefaultInclinationDegrees);
}

void ApplyCameraDefaults(v1::Camera& camera) {
  if (camera.projection() == v1::PROJECTION_UNSPECIFIED) camera.set_projection(v1::PROJECTION_PERSPECTIVE);
  if (IsZero(camera.up())) SetVec3(camera.mutable_up(), 0, 0, 1);
  if (camera.fov_y_degrees() == 0) camera.set_fov_y_degrees(kDefaultFovYDegrees);
  if (camera.ortho_height() == 0) camera.set_ortho_height(kDefaultOrthoHeight);
  if (camera.near() == 0) camera.set_near(kDefaultNear);
  if (camera.far() == 0) camera.set_far(kDefaultFar);
}

void ApplyLightDefaults(v1::Light& light) {
  if (light.type() == v1::LIGHT_TYPE_UNSPECIFIED) light.set_type(v1::LIGHT_TYPE_DIRECTIONAL);
  if (light.intensity() == 0) light.set_intensity(kDefaultLightIntensity);
  if (!light.has_colour()) SetGrey(light.mutable_colour(), 1);
}

void ApplyObjectDefaults(v1::SceneObject& object) {
  if (IsZero(object.transform().scale())) SetVec3(object.mutable_transform()->mutable_scale(), 1, 1, 1);
  if (!object.has_base_colour()) SetGrey(object.mutable_base_colour(), kDefaultBaseColour);
  if (!object.has_fabric()) return;
  v1::FabricBinding& binding = *object.mutable_fabric();
  *binding.mutable_fabric() = WithDefaults(binding.fabric());
  if (binding.has_precompute()) *binding.mutable_precompute() = WithDefaults(binding.precompute());
  if (binding.repeat_u() == 0) binding.set_repeat_u(kDefaultRepeat);
  if (binding.repeat_v() == 0) binding.set_repeat_v(kDefaultRepeat);
}

}  // namespace

KnitRepeat KnitPatternRepeat(const v1::KnitSpec& knit) {
  switch (knit.pattern()) {
    case v1::KNIT_PATTERN_GARTER: return {1, 2};
    case v1::KNIT_PATTERN_RIB: return {knit.rib_knit() + knit.rib_purl(), 1};
    case v1::KNIT_PATTERN_SEED: return {2, 2};
    default: return {1, 1};
  }
}

bool IsValidSatinMove(uint32_t n, uint32_t m) { return 1 < m && m + 1 < n && std::gcd(m, n) == 1; }

uint32_t SmallestSatinMove(uint32_t n) {
  for (uint32_t m = 2; m + 1 < n; ++m) {
    if (IsValidSatinMove(n, m)) return m;
  }
  return 0;
}

bool AcquiresTransmission(const v1::FabricSpec& fabric, const v1::PrecomputeSettings& settings) {
  if (settings.has_transmission()) return settings.transmission();
  for (const v1::YarnSpec& yarn : fabric.yarns()) {
    if (yarn.shading() == v1::YARN_SHADING_MICROFLAKE) return true;
  }
  return false;
}

bool IsTableMethod(v1::FabricMethod method) {
  return method == v1::FABRIC_METHOD_TABULATED || method == v1::FABRIC_METHOD_FACTORED ||
         method == v1::FABRIC_METHOD_NEURAL;
}

v1::PrecomputeSettings WithDefaults(v1::PrecomputeSettings settings) {
  // The table methods interpolate the stored views themselves: an odd grid puts a view
  // at the zenith, which head-on views then need not blend with parallax; and they keep
  // what a texel saw rather than a fit that smooths it, so finer texels pay off near by
  // (docs/accuracy.md).
  const bool table = IsTableMethod(settings.method());
  if (settings.spatial_resolution() == 0) {
    settings.set_spatial_resolution(table ? kDefaultTableSpatialResolution : kDefaultSpatialResolution);
  }
  if (settings.view_directions() == 0) {
    settings.set_view_directions(table ? kDefaultTableViewDirections : kDefaultDirections);
  }
  if (settings.light_directions() == 0) settings.set_light_directions(kDefaultDirections);
  if (settings.lobes() == 0) settings.set_lobes(kDefaultLobes);
  if (!settings.has_lookup_table()) settings.set_lookup_table(true);
  if (settings.mip_levels() == v1::MIP_LEVELS_UNSPECIFIED) settings.set_mip_levels(v1::MIP_LEVELS_AUTO);
  if (settings.lut_change_threshold() == 0) settings.set_lut_change_threshold(kDefaultLutChangeThreshold);
  if (settings.max_alternations() == 0) settings.set_max_alternations(kDefaultMaxAlternations);
  if (settings.max_lm_iterations() == 0) settings.set_max_lm_iterations(kDefaultMaxLmIterations);
  if (!settings.has_indirect_bounces()) settings.set_indirect_bounces(kDefaultIndirectBounces);
  if (settings.supersampling() == 0) settings.set_supersampling(kDefaultSupersampling);
  if (!settings.has_half_float()) settings.set_half_float(true);
  if (settings.method() == v1::FABRIC_METHOD_UNSPECIFIED) settings.set_method(v1::FABRIC_METHOD_SVBRDF);
  // The table methods render the stored views themselves, blended with the parallax
  // of whatever lies off the plane: on a plane at the depth each view sees, the least
  // (docs/accuracy.md). svbrdf's planner figures were measured on the top face.
  if (settings.sampling_plane() == v1::SAMPLING_PLANE_UNSPECIFIED) {
    settings.set_sampling_plane(IsTableMethod(settings.method()) ? v1::SAMPLING_PLANE_VIEW_DEPTH
                                                                 : v1::SAMPLING_PLANE_TOP);
  }
  // Only a method's own settings get its defaults: the others' keys and manifests
  // stay as they were before it.
  if (settings.method() == v1::FABRIC_METHOD_FACTORED && settings.factored().rank() == 0) {
    settings.mutable_factored()->set_rank(kDefaultFactoredRank);
  }
  if (settings.method() == v1::FABRIC_METHOD_NEURAL) {
    v1::NeuralSettings& neural = *settings.mutable_neural();
    if (neural.channels() == 0) neural.set_channels(kDefaultNeuralChannels);
    if (neural.hidden() == 0) neural.set_hidden(kDefaultNeuralHidden);
    if (neural.steps() == 0) neural.set_steps(kDefaultNeuralSteps);
    if (!neural.has_frequencies()) neural.set_frequencies(kDefaultNeuralFrequencies);
  }
  return settings;
}

v1::FabricSpec WithDefaults(v1::FabricSpec fabric) {
  // Without a structure the yarn radius has no unit; validation reports it.
  if (fabric.structure_case() == v1::FabricSpec::STRUCTURE_NOT_SET) return fabric;
  const bool knit = fabric.has_knit();
  if (knit) {
    ApplyKnitDefaults(*fabric.mutable_knit());
  } else {
    ApplyWovenDefaults(*fabric.mutable_woven());
  }
  if (fabric.yarns().empty()) fabric.add_yarns();
  for (v1::YarnSpec& yarn : *fabric.mutable_yarns()) {
    ApplyYarnDefaults(yarn, knit ? kDefaultKnitYarnRadius : kDefaultWovenYarnRadius);
  }
  return fabric;
}

v1::RenderSettings WithDefaults(v1::RenderSettings settings) {
  if (settings.method() == v1::RENDER_METHOD_UNSPECIFIED) settings.set_method(v1::RENDER_METHOD_SVBRDF);
  if (settings.width() == 0) settings.set_width(kDefaultWidth);
  if (settings.height() == 0) settings.set_height(kDefaultHeight);
  if (settings.msaa_samples() == 0) {
    // The lumislice renderer's samples are whole rays through the yarn: one by default.
    settings.set_msaa_samples(settings.method() == v1::RENDER_METHOD_LUMISLICE ? 1 : kDefaultMsaaSamples);
  }
  if (settings.level_mode() == v1::LEVEL_MODE_UNSPECIFIED) settings.set_level_mode(v1::LEVEL_MODE_TRILINEAR);
  // Bilinear: more accurate than the paper's nearest lookup on the bench set, within
  // the frame-time goal on llvmpipe (figures: docs/accuracy.md, docs/gpu.md).
  if (settings.texel_filter() == v1::TEXEL_FILTER_UNSPECIFIED) settings.set_texel_filter(v1::TEXEL_FILTER_BILINEAR);
  if (settings.shading_rate() == v1::SHADING_RATE_UNSPECIFIED) settings.set_shading_rate(v1::SHADING_RATE_PIXEL);
  if (settings.shadow_map_size() == 0) settings.set_shadow_map_size(kDefaultShadowMapSize);
  if (settings.reference_samples() == 0) settings.set_reference_samples(kDefaultReferenceSamples);
  // `format` stays unspecified: it is resolved from the output file name.
  return settings;
}

v1::SceneSpec WithDefaults(v1::SceneSpec scene) {
  for (v1::SceneObject& object : *scene.mutable_objects()) ApplyObjectDefaults(object);
  ApplyCameraDefaults(*scene.mutable_camera());
  for (v1::Light& light : *scene.mutable_lights()) ApplyLightDefaults(light);
  *scene.mutable_render() = WithDefaults(scene.render());
  return scene;
}

v1::AnimationSpec WithDefaults(v1::AnimationSpec animation) {
  v1::KnitClothSpec& cloth = *animation.mutable_cloth();
  if (cloth.course_spacing() == 0) cloth.set_course_spacing(1.0f);
  if (cloth.wale_spacing() == 0) cloth.set_wale_spacing(1.0f);
  const auto zero = [](const v1::Vec3& v) { return v.x() == 0 && v.y() == 0 && v.z() == 0; };
  if (zero(cloth.course_axis())) cloth.mutable_course_axis()->set_x(1.0f);
  if (zero(cloth.wale_axis())) cloth.mutable_wale_axis()->set_y(1.0f);
  if (cloth.has_fabric()) *cloth.mutable_fabric() = WithDefaults(cloth.fabric());
  if (animation.frames_per_second() == 0) animation.set_frames_per_second(kDefaultFramesPerSecond);
  for (v1::ColliderSpec& collider : *animation.mutable_colliders()) {
    if (collider.has_mesh() && zero(collider.mesh().transform().scale())) {
      SetVec3(collider.mutable_mesh()->mutable_transform()->mutable_scale(), 1, 1, 1);
    }
  }
  return animation;
}

uint64_t AnimationFrames(const v1::AnimationSpec& animation) {
  const double frames = double{animation.duration_seconds()} * animation.frames_per_second();
  if (!(frames > 0.0) || !std::isfinite(frames)) return 0;
  return static_cast<uint64_t>(std::ceil(frames - 1e-3));
}

}  // namespace loom
