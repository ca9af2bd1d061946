// loom-lab render: a scene to an image. `svbrdf` renders with the fitted BRDF
// arrays on the GPU (each distinct fabric precomputed once in this process);
// `reference` ray traces the real yarn geometry shell-mapped onto the surfaces.

#include <cstdio>
#include <map>

#include "core/render/reference_renderer.h"
#include "core/render/scene_render.h"
#include "core/spec/defaults.h"
#include "core/spec/spec_json.h"
#include "core/spec/validate.h"
#include "core/util/stopwatch.h"
#include "lab/fabric_cache.h"
#include "lab/lab_command.h"

namespace loom::lab {
namespace {

// Renders with svbrdf, fitting each distinct fabric in this process first (or
// loading it from `cache`); adds its figures to `figures`.
Image RenderSvbrdf(const v1::SceneSpec& scene, const std::vector<SceneMesh>& meshes, const GlFlags& gl,
                   const std::filesystem::path& cache, nlohmann::json& figures) {
  const Stopwatch stopwatch;
  std::map<std::string, FittedFabric> fitted;
  FittedFabrics fits;
  for (const SceneFabric& fabric : SceneFabrics(scene)) {
    fits[fabric.key] = &fitted.emplace(fabric.key, LoadOrPrecompute(fabric, cache).fit).first->second;
  }
  figures["fabrics"] = fits.size();
  figures["precompute_seconds"] = stopwatch.Seconds();  // loading, where the cache had them

  const auto context = MakeContext(gl);
  SvbrdfRenderer renderer(*context);
  RenderedFrame frame = RenderScene(renderer, scene, meshes, fits);
  figures["frame_ms"] = frame.cpu_ms;
  figures["gpu_ms"] = frame.gpu_ms;
  figures["device"] = DeviceJson(context->info());
  return std::move(frame.image);
}

Image RenderReference(const v1::SceneSpec& scene, const std::vector<SceneMesh>& meshes, nlohmann::json& figures) {
  ReferenceRenderer renderer;
  ReferenceFrame frame = renderer.Render(scene, meshes);
  figures["frame_ms"] = frame.cpu_ms;
  figures["rays"] = frame.rays;
  figures["samples_per_pixel"] = scene.render().reference_samples();
  return std::move(frame.image);
}

}  // namespace

LabCommand AddRenderCommand(CLI::App& app, const LabFlags& flags) {
  struct Options {
    std::string scene, out, method, fabric_cache;
    GlFlags gl;
  };
  auto options = std::make_shared<Options>();
  auto* command = app.add_subcommand("render", "Render a scene to an image (.png sRGB or .exr linear)");
  command->add_option("scene", options->scene, "Scene spec file (JSON); OBJ paths are relative to it")->required();
  command->add_option("--out,-o", options->out, "Output image")->required();
  command->add_option("--method", options->method, "Render method (default: the scene's render.method)")
      ->check(CLI::IsMember({"svbrdf", "reference"}));
  command->add_option("--fabric-cache", options->fabric_cache,
                      "Directory of fabric assets by cache key: svbrdf loads a fabric found there and stores "
                      "one it had to precompute");
  AddGlFlags(command, &options->gl);
  return {command, [&flags, options] {
            FormatFromPath(options->out);  // reject a bad extension before any work
            v1::SceneSpec scene = LoadSpecFile<v1::SceneSpec>(options->scene, "scene");
            if (options->method == "reference") scene.mutable_render()->set_method(v1::RENDER_METHOD_REFERENCE);
            if (options->method == "svbrdf") scene.mutable_render()->set_method(v1::RENDER_METHOD_SVBRDF);
            scene = WithDefaults(scene);
            ValidateOrThrow(scene);
            const auto meshes =
                BuildSceneGeometry(scene, FileMeshResolver(std::filesystem::path(options->scene).parent_path()));
            const bool reference = scene.render().method() == v1::RENDER_METHOD_REFERENCE;
            nlohmann::json figures = {{"out", options->out}, {"method", reference ? "reference" : "svbrdf"}};
            const Image image =
                reference ? RenderReference(scene, meshes, figures) : RenderSvbrdf(scene, meshes, options->gl, options->fabric_cache, figures);
            WriteImage(image, options->out);
            figures["width"] = image.width;
            figures["height"] = image.height;
            if (flags.json) {
              PrintJson(figures);
            } else {
              std::printf("wrote %s (%dx%d, %s) in %.1f ms\n", options->out.c_str(), image.width, image.height,
                          figures["method"].get<std::string>().c_str(), figures["frame_ms"].get<double>());
            }
            return 0;
          }};
}

}  // namespace loom::lab
