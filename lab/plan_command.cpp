// loom-lab plan: the least precompute that serves a scene (core/plan/precompute_plan.h),
// and what it chose and why. `--distill CSV...` turns a sweep's CSVs into the table
// the planner is compiled with (core/plan/standard_sweep_table.inc).

#include <cstdio>
#include <filesystem>
#include <vector>

#include "core/methods/fabric_method.h"
#include "core/plan/precompute_plan.h"
#include "core/spec/defaults.h"
#include "core/spec/spec_json.h"
#include "core/spec/validate.h"
#include "core/util/error.h"
#include "lab/csv_table.h"
#include "lab/lab_command.h"
#include "lab/sweep_distill.h"

namespace loom::lab {
namespace {

nlohmann::json SettingsJson(const v1::PrecomputeSettings& settings) {
  return nlohmann::json::parse(SpecToJson(settings, false));
}

nlohmann::json PlanJson(const ScenePlan& plan) {
  nlohmann::json fabrics = nlohmann::json::array();
  for (const FabricPlan& fabric : plan.fabrics) {
    fabrics.push_back({{"key", fabric.key},
                       {"objects", fabric.objects},
                       {"explicit_settings", fabric.explicit_settings},
                       {"tile_pixels_largest", fabric.footprint.largest_pixels},
                       {"tile_pixels_smallest", fabric.footprint.smallest_pixels},
                       {"visible_triangles", fabric.footprint.visible_triangles},
                       {"footprint_class", FootprintClassName(fabric.footprint_class)},
                       {"footprint_resolution", fabric.footprint_resolution},
                       {"fabric_kind", FabricKindName(fabric.fabric_kind)},
                       {"fabric_kind_measured", fabric.kind_measured},
                       {"chosen", fabric.chosen},
                       {"settings", SettingsJson(fabric.settings)},
                       {"predicted_psnr_loss_db", fabric.predicted_psnr_loss_db},
                       {"predicted_precompute_ratio", fabric.predicted_precompute_ratio},
                       {"predicted_bytes_ratio", fabric.predicted_bytes_ratio},
                       {"reasons", fabric.reasons}});
  }
  return {{"error_budget_db", plan.error_budget_db}, {"fabrics", fabrics}};
}

void PrintPlan(const ScenePlan& plan) {
  std::printf("error budget: %.2f dB of PSNR against the default settings\n", plan.error_budget_db);
  for (const FabricPlan& fabric : plan.fabrics) {
    std::string objects;
    for (const std::string& object : fabric.objects) objects += (objects.empty() ? "" : ", ") + object;
    std::printf("\nfabric %s (objects: %s)\n", fabric.key.substr(0, 12).c_str(), objects.c_str());
    const v1::PrecomputeSettings& s = fabric.settings;
    const FabricMethod& method = MethodOf(s.method());
    std::printf("  settings: %s, %u texels a side, %u views x %u lights, supersampling %u",
                std::string(method.name()).c_str(), s.spatial_resolution(), s.view_directions(), s.light_directions(),
                s.supersampling());
    // svbrdf's fit, where it reaches the method's asset (its key keeps it).
    const v1::PrecomputeSettings keyed = method.KeySettings(s);
    if (keyed.lobes() != 0) std::printf(", %u lobes, LUT %s", s.lobes(), s.lookup_table() ? "on" : "off");
    const std::string own = method.OwnSettings(s);
    std::printf("%s%s\n", own.empty() ? "" : ", ", own.c_str());
    if (!fabric.explicit_settings) {
      std::printf("  predicted against the defaults: PSNR -%.2f dB at worst, precompute x%.3f, bytes x%.3f\n",
                  fabric.predicted_psnr_loss_db, fabric.predicted_precompute_ratio, fabric.predicted_bytes_ratio);
    }
    std::printf("  why:\n");
    for (const std::string& reason : fabric.reasons) std::printf("    - %s\n", reason.c_str());
  }
}

}  // namespace

LabCommand AddPlanCommand(CLI::App& app, const LabFlags& flags) {
  struct Options {
    std::string scene;
    std::vector<std::filesystem::path> sweep, distill, methods;
    double budget = kDefaultErrorBudgetDb;
  };
  auto options = std::make_shared<Options>();
  auto* command = app.add_subcommand(
      "plan", "The least precompute that serves a scene's fabrics within an error budget, and why");
  command->add_option("scene", options->scene, "Scene spec file (JSON)");
  command->add_option("--error-budget", options->budget,
                      "PSNR (dB) the plan may lose against the default settings (default 0.5)");
  // One CSV per --sweep (repeat it for more), so that the scene may come after.
  command
      ->add_option("--sweep", options->sweep,
                   "Plan from this sweep CSV instead of the measurements compiled in; repeat for a sweep's "
                   "repeats under other seeds")
      ->allow_extra_args(false);
  command->add_option("--distill", options->distill,
                      "Print the measured variations of these sweep CSVs (a sweep and its repeats under other "
                      "seeds) as the compiled-in table (C++), plan nothing");
  command
      ->add_option("--methods", options->methods,
                   "With --distill or --sweep: a sweep of other fabric methods (bench/sweep_methods.json), distilled "
                   "on its own: its methods at their defaults join the variations")
      ->allow_extra_args(false);
  return {command, [&flags, options] {
            // The settings variations of the sweep and its repeats, then the methods
            // of a methods sweep (its own baseline scenes: a class complete there).
            const auto distill = [&options](const std::vector<std::filesystem::path>& sweep) {
              std::vector<MeasuredVariation> variations = DistillSweep(ReadCsvs(sweep));
              if (!options->methods.empty()) {
                for (const MeasuredVariation& v : DistillSweep(ReadCsvs(options->methods))) {
                  if (v.method != v1::FABRIC_METHOD_UNSPECIFIED) variations.push_back(v);
                }
              }
              return variations;
            };
            if (!options->distill.empty()) {
              const std::string table = VariationsAsCpp(distill(options->distill));
              std::printf("// Generated by: loom-lab plan --distill");
              for (const auto& path : options->distill) std::printf(" %s", path.string().c_str());
              if (!options->methods.empty()) std::printf(" --methods");
              for (const auto& path : options->methods) std::printf(" %s", path.string().c_str());
              std::printf("\n%s", table.c_str());
              return 0;
            }
            if (options->scene.empty()) throw Error(ErrorCode::kInvalidArgument, "scene: a scene file is required");
            v1::SceneSpec scene = WithDefaults(LoadSpecFile<v1::SceneSpec>(options->scene, "scene"));
            ValidateOrThrow(scene);
            const auto meshes =
                BuildSceneGeometry(scene, FileMeshResolver(std::filesystem::path(options->scene).parent_path()));
            const std::vector<MeasuredVariation> variations =
                options->sweep.empty() ? StandardSweepVariations() : distill(options->sweep);
            const ScenePlan plan = PlanScene(scene, meshes, options->budget, variations);
            if (flags.json) {
              PrintJson(PlanJson(plan));
            } else {
              PrintPlan(plan);
            }
            return 0;
          }};
}

}  // namespace loom::lab
