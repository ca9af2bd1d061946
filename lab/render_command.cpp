// loom-lab render: a scene to an image with the svbrdf renderer. Each distinct
// fabric (by cache key) is precomputed once in this process: geometry →
// acquisition → fit.

#include <chrono>
#include <cstdio>
#include <map>

#include "core/precompute/fabric_precompute.h"
#include "core/render/svbrdf_renderer.h"
#include "core/spec/defaults.h"
#include "core/spec/fabric_key.h"
#include "core/spec/spec_json.h"
#include "core/spec/validate.h"
#include "lab/lab_command.h"
#include "lab/progress_bar.h"

namespace loom::lab {
namespace {

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

FittedFabric Precompute(const v1::FabricSpec& fabric, const v1::PrecomputeSettings& settings, const std::string& label) {
  ProgressBar bar("precompute " + label);
  return PrecomputeFabric(fabric, settings, [&bar](double f, std::string_view stage) { bar.Update(f, stage); });
}

}  // namespace

LabCommand AddRenderCommand(CLI::App& app, const LabFlags& flags) {
  struct Options {
    std::string scene, out, method = "svbrdf";
    GlFlags gl;
  };
  auto options = std::make_shared<Options>();
  auto* command = app.add_subcommand("render", "Render a scene to an image (.png sRGB or .exr linear)");
  command->add_option("scene", options->scene, "Scene spec file (JSON); OBJ paths are relative to it")->required();
  command->add_option("--out,-o", options->out, "Output image")->required();
  command->add_option("--method", options->method, "Render method")->check(CLI::IsMember({"svbrdf"}));
  AddGlFlags(command, &options->gl);
  return {command, [&flags, options] {
            FormatFromPath(options->out);  // reject a bad extension before any work
            const v1::SceneSpec scene = WithDefaults(LoadSpecFile<v1::SceneSpec>(options->scene, "scene"));
            ValidateOrThrow(scene);
            const auto start = std::chrono::steady_clock::now();
            const auto meshes =
                BuildSceneGeometry(scene, FileMeshResolver(std::filesystem::path(options->scene).parent_path()));

            // One fit per distinct fabric.
            std::map<std::string, FittedFabric> fits;
            std::vector<std::string> keys(meshes.size());
            for (size_t i = 0; i < meshes.size(); ++i) {
              const v1::SceneObject& object = *meshes[i].object;
              if (!object.has_fabric()) continue;
              const v1::FabricBinding& binding = object.fabric();
              keys[i] = FabricKey(binding.fabric(), binding.precompute());
              if (!fits.contains(keys[i])) {
                fits.emplace(keys[i], Precompute(binding.fabric(), binding.precompute(), keys[i].substr(0, 8)));
              }
            }
            const double precompute_seconds = SecondsSince(start);

            const auto context = MakeContext(options->gl);
            SvbrdfRenderer renderer(*context);
            std::map<std::string, std::unique_ptr<FabricTextures>> textures;
            std::vector<const FabricTextures*> fabrics(meshes.size(), nullptr);
            for (size_t i = 0; i < meshes.size(); ++i) {
              if (keys[i].empty()) continue;
              auto& uploaded = textures[keys[i]];
              if (!uploaded) {
                uploaded = std::make_unique<FabricTextures>(FabricTextureData::FromFit(fits.at(keys[i])),
                                                            meshes[i].object->fabric().precompute().half_float());
              }
              fabrics[i] = uploaded.get();
            }
            const RenderedFrame frame = renderer.Render(scene, meshes, fabrics);
            WriteImage(frame.image, options->out);
            if (flags.json) {
              PrintJson({{"out", options->out},
                         {"method", options->method},
                         {"width", frame.image.width},
                         {"height", frame.image.height},
                         {"frame_ms", frame.cpu_ms},
                         {"gpu_ms", frame.gpu_ms},
                         {"fabrics", fits.size()},
                         {"precompute_seconds", precompute_seconds},
                         {"device", DeviceJson(context->info())}});
            } else {
              std::printf("wrote %s (%dx%d) in %.1f ms (GPU %.2f ms) on %s; %zu fabric(s) precomputed in %.1f s\n",
                          options->out.c_str(), frame.image.width, frame.image.height, frame.cpu_ms, frame.gpu_ms,
                          context->info().gl_renderer.c_str(), fits.size(), precompute_seconds);
            }
            return 0;
          }};
}

}  // namespace loom::lab
