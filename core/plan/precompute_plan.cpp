#include "core/plan/precompute_plan.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "core/spec/defaults.h"
#include "core/spec/fabric_key.h"
#include "core/util/error.h"

namespace loom {
namespace {

std::string Format(const char* format, auto... values) {
  char text[512];
  std::snprintf(text, sizeof text, format, values...);
  return text;
}

uint32_t NextPowerOfTwo(double value) {
  uint32_t power = 1;
  while (power < value && power < (1u << 30)) power *= 2;
  return power;
}

std::string ClassName(const FabricPlan& plan) {
  return std::string(FootprintClassName(plan.footprint_class)) + ", " +
         (plan.kind_measured ? FabricKindName(plan.fabric_kind) : "every kind");
}

void Apply(const MeasuredVariation& v, v1::PrecomputeSettings& settings) {
  if (v.method != v1::FABRIC_METHOD_UNSPECIFIED) {
    // The method at its own defaults but the baseline's texels, lights and rays, as the
    // sweep measured it (lab/sweep_distill.cpp MethodVariation).
    v1::PrecomputeSettings method;
    method.set_method(v.method);
    method.set_spatial_resolution(settings.spatial_resolution());
    method.set_light_directions(settings.light_directions());
    method.set_supersampling(settings.supersampling());
    settings = WithDefaults(method);
  }
  if (v.spatial_resolution != 0) settings.set_spatial_resolution(v.spatial_resolution);
  if (v.supersampling != 0) settings.set_supersampling(v.supersampling);
  if (v.directions != 0) {
    settings.set_view_directions(v.directions);
    settings.set_light_directions(v.directions);
  }
  if (v.lobes != 0) settings.set_lobes(v.lobes);
  if (v.lookup_table >= 0) settings.set_lookup_table(v.lookup_table == 1);
}

// The measurements of the fabric's class of scene (footprint class and kind). For a
// kind the table does not hold at this footprint class, each configuration's
// measurements over every kind, merged pessimistically: the lowest worst-case
// change, the highest ratios; so too for a configuration measured on fewer than
// kMinClassScenes scenes of the class.
std::vector<MeasuredVariation> ApplicableVariations(FabricPlan& plan, const std::vector<MeasuredVariation>& variations) {
  std::vector<MeasuredVariation> same_class, any_kind;
  for (const MeasuredVariation& v : variations) {
    if (v.footprint != plan.footprint_class) continue;
    if (v.fabric_kind == plan.fabric_kind) same_class.push_back(v);
    const auto merged = std::find_if(any_kind.begin(), any_kind.end(),
                                     [&](const MeasuredVariation& m) { return m.configuration == v.configuration; });
    if (merged == any_kind.end()) {
      any_kind.push_back(v);
      continue;
    }
    merged->psnr_change_db = std::min(merged->psnr_change_db, v.psnr_change_db);
    merged->worst_psnr_change_db = std::min(merged->worst_psnr_change_db, v.worst_psnr_change_db);
    merged->precompute_ratio = std::max(merged->precompute_ratio, v.precompute_ratio);
    merged->bytes_ratio = std::max(merged->bytes_ratio, v.bytes_ratio);
    merged->scenes += v.scenes;
  }
  plan.kind_measured = !same_class.empty();
  if (plan.kind_measured) {
    for (MeasuredVariation& v : same_class) {
      if (v.scenes >= kMinClassScenes) continue;
      const auto merged = std::find_if(any_kind.begin(), any_kind.end(),
                                       [&](const MeasuredVariation& m) { return m.configuration == v.configuration; });
      plan.reasons.push_back(Format("%s: measured on %d %s scenes only: taken at the worst of every kind %s",
                                    v.configuration.c_str(), v.scenes, FabricKindName(plan.fabric_kind),
                                    FootprintClassName(plan.footprint_class)));
      v = *merged;
    }
    return same_class;
  }
  plan.reasons.push_back(Format("no measurements of %s fabrics %s: planned from the worst of every kind",
                                FabricKindName(plan.fabric_kind), FootprintClassName(plan.footprint_class)));
  return any_kind;
}

void Plan(FabricPlan& plan, double budget, const std::vector<MeasuredVariation>& variations) {
  const v1::PrecomputeSettings defaults = WithDefaults(v1::PrecomputeSettings());
  plan.settings = defaults;
  if (plan.footprint.visible_triangles == 0) {
    // Nothing of it is on screen: the smallest settings the table knows serve.
    plan.footprint_resolution = kMinPlannedResolution;
    plan.footprint_class = FootprintClass::kFar;
    plan.reasons.push_back("no triangle of it is visible: planned as far");
  } else {
    plan.footprint_class = ClassifyFootprint(plan.footprint.largest_pixels);
    plan.footprint_resolution = std::clamp(NextPowerOfTwo(std::ceil(plan.footprint.largest_pixels - 1e-6)),
                                           kMinPlannedResolution, defaults.spatial_resolution());
    plan.reasons.push_back(Format(
        "a tile spans at most %.1f px on screen (%d visible triangles): %s; no more than %u texels a side can show",
        plan.footprint.largest_pixels, plan.footprint.visible_triangles, FootprintClassName(plan.footprint_class),
        plan.footprint_resolution));
  }

  plan.fabric_kind = ClassifyFabric(plan.fabric);
  plan.reasons.push_back(Format("the fabric is %s", FabricKindName(plan.fabric_kind)));

  const std::vector<MeasuredVariation> applicable = ApplicableVariations(plan, variations);
  std::vector<const MeasuredVariation*> candidates;
  for (const MeasuredVariation& v : applicable) {
    if (v.spatial_resolution != 0 && v.spatial_resolution < plan.footprint_resolution) {
      plan.reasons.push_back(Format("not %s: %u texels a side are fewer than the footprint can show",
                                    v.configuration.c_str(), v.spatial_resolution));
      continue;
    }
    if (v.bytes_ratio > kMaxPlannedBytesRatio) {
      plan.reasons.push_back(Format("not %s: its asset measured x%.1f the defaults' bytes, more than the x%.0f a plan "
                                    "may grow it",
                                    v.configuration.c_str(), v.bytes_ratio, kMaxPlannedBytesRatio));
      continue;
    }
    if (!(v.precompute_ratio < 1.0)) {
      plan.reasons.push_back(Format("not %s: measured precompute x%.3f of the defaults: saves nothing",
                                    v.configuration.c_str(), v.precompute_ratio));
      continue;
    }
    candidates.push_back(&v);
  }
  std::stable_sort(candidates.begin(), candidates.end(), [](const auto* a, const auto* b) {
    return a->precompute_ratio < b->precompute_ratio;
  });
  // The cheapest measured variation within the budget on every scene of the class,
  // and only one: the sweep measures variations one at a time, and their
  // combination is not the sum of their losses (precompute_plan.h).
  for (const MeasuredVariation* v : candidates) {
    if (!plan.chosen.empty()) {
      plan.reasons.push_back(Format("not %s: saves less (precompute x%.3f) than %s, and variations are measured one "
                                    "at a time",
                                    v->configuration.c_str(), v->precompute_ratio, plan.chosen.front().c_str()));
      continue;
    }
    const double loss = std::max(0.0, -v->worst_psnr_change_db);
    if (loss > budget + 1e-9) {
      plan.reasons.push_back(Format("not %s: measured %+.2f dB at worst (mean %+.2f, %s, %d scenes) would exceed the "
                                    "%.2f dB budget",
                                    v->configuration.c_str(), v->worst_psnr_change_db, v->psnr_change_db,
                                    ClassName(plan).c_str(), v->scenes, budget));
      continue;
    }
    Apply(*v, plan.settings);
    plan.chosen.push_back(v->configuration);
    plan.predicted_psnr_loss_db = loss;
    plan.predicted_precompute_ratio = v->precompute_ratio;
    plan.predicted_bytes_ratio = v->bytes_ratio;
    plan.reasons.push_back(Format("%s: measured %+.2f dB at worst (mean %+.2f), precompute x%.3f, bytes x%.3f (%s, %d "
                                  "scenes)",
                                  v->configuration.c_str(), v->worst_psnr_change_db, v->psnr_change_db,
                                  v->precompute_ratio, v->bytes_ratio, ClassName(plan).c_str(), v->scenes));
  }
  if (plan.chosen.empty()) plan.reasons.push_back("no measured variation fits the budget: the defaults");
}

}  // namespace

ScenePlan PlanScene(const v1::SceneSpec& scene, const std::vector<SceneMesh>& meshes, double error_budget_db,
                    const std::vector<MeasuredVariation>& variations) {
  if (!std::isfinite(error_budget_db) || error_budget_db < 0.0) {
    throw Error(ErrorCode::kInvalidArgument,
                Format("error budget: %g dB is not a finite number >= 0 (the PSNR the plan may lose)", error_budget_db));
  }
  ScenePlan plan;
  plan.error_budget_db = error_budget_db;
  // One plan per distinct fabric; objects with explicit settings are grouped by
  // their cache key and kept as they are.
  std::map<std::string, size_t> by_group;
  for (size_t i = 0; i < meshes.size(); ++i) {
    const v1::SceneObject& object = *meshes[i].object;
    if (!object.has_fabric()) continue;
    const v1::FabricBinding& binding = object.fabric();
    const bool explicit_settings = binding.has_precompute();
    const std::string group = (explicit_settings ? "explicit:" : "planned:") +
                              FabricKey(binding.fabric(), explicit_settings ? binding.precompute()
                                                                            : v1::PrecomputeSettings());
    auto [found, added] = by_group.emplace(group, plan.fabrics.size());
    if (added) {
      FabricPlan fabric;
      fabric.fabric = binding.fabric();
      fabric.explicit_settings = explicit_settings;
      fabric.settings = WithDefaults(binding.precompute());
      plan.fabrics.push_back(std::move(fabric));
    }
    FabricPlan& fabric = plan.fabrics[found->second];
    fabric.objects.push_back(object.name().empty() ? "#" + std::to_string(i) : object.name());
    const TileFootprint footprint = MeasureTileFootprint(scene, meshes[i]);
    if (footprint.visible_triangles > 0) {
      fabric.footprint.largest_pixels = std::max(fabric.footprint.largest_pixels, footprint.largest_pixels);
      fabric.footprint.smallest_pixels = fabric.footprint.visible_triangles == 0
                                             ? footprint.smallest_pixels
                                             : std::min(fabric.footprint.smallest_pixels, footprint.smallest_pixels);
      fabric.footprint.visible_triangles += footprint.visible_triangles;
    }
  }
  for (FabricPlan& fabric : plan.fabrics) {
    if (fabric.explicit_settings) {
      fabric.reasons.push_back("the scene gives its precompute settings: kept");
    } else {
      Plan(fabric, error_budget_db, variations);
    }
    fabric.key = FabricKey(fabric.fabric, fabric.settings);
  }
  return plan;
}

v1::SceneSpec ApplyPlan(v1::SceneSpec scene, const ScenePlan& plan) {
  for (v1::SceneObject& object : *scene.mutable_objects()) {
    if (!object.has_fabric() || object.fabric().has_precompute()) continue;
    const std::string key = FabricKey(object.fabric().fabric(), v1::PrecomputeSettings());
    for (const FabricPlan& fabric : plan.fabrics) {
      if (!fabric.explicit_settings && FabricKey(fabric.fabric, v1::PrecomputeSettings()) == key) {
        *object.mutable_fabric()->mutable_precompute() = fabric.settings;
      }
    }
  }
  return scene;
}

}  // namespace loom
