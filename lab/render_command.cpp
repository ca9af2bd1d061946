// loom-lab render: a scene to an image. The GPU renders each fabric by its method
// (svbrdf: the fitted BRDF arrays; tabulated: the samples), each distinct fabric
// precomputed once in this process; `reference` ray traces the real yarn geometry
// shell-mapped onto the surfaces; `lumislice` draws knit cloth as volumetric yarn.

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <map>
#include <optional>
#include <string>
#include <string_view>

#include "core/render/lumislice_renderer.h"
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

// The enum value behind a short option value: ("LEVEL_MODE_", "anisotropic") → LEVEL_MODE_ANISOTROPIC.
// The option's IsMember check has already limited `value` to known names.
std::string EnumName(std::string_view prefix, std::string value) {
  for (char& c : value) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return std::string(prefix) + value;
}

// Renders on the GPU, precomputing each distinct fabric in this process first (or
// loading it from `cache`); adds its figures to `figures`. `frames` renders of the
// same renderer: frame_ms and gpu_ms are the fastest, as in the sweep, since the
// first frame also pays for compiling a shader variant and allocating the shadow
// maps (first_frame_ms says how much).
Image RenderGpu(const v1::SceneSpec& scene, const std::vector<SceneMesh>& meshes, const GlFlags& gl,
                   const std::filesystem::path& cache, int frames, nlohmann::json& figures) {
  const Stopwatch stopwatch;
  std::map<std::string, CachedFabric> built;
  FabricAssets fits;
  std::vector<std::string> names;  // the fabrics' methods, in order of first use
  for (const SceneFabric& fabric : SceneFabrics(scene)) {
    const FabricAsset* asset = built.emplace(fabric.key, LoadOrPrecompute(fabric, cache)).first->second.asset.get();
    fits[fabric.key] = asset;
    const std::string name(asset->method().name());
    if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
  }
  std::string methods;
  for (const std::string& name : names) methods += (methods.empty() ? "" : "+") + name;
  figures["method"] = methods.empty() ? "svbrdf" : methods;
  figures["fabrics"] = fits.size();
  figures["precompute_seconds"] = stopwatch.Seconds();  // loading, where the cache had them

  const auto context = MakeContext(gl);
  GpuRenderer renderer(*context);
  RenderedFrame frame = RenderScene(renderer, scene, meshes, fits);
  figures["first_frame_ms"] = frame.cpu_ms;
  double frame_ms = frame.cpu_ms;
  RenderedFrame fastest = frame;  // by GPU time, its passes with it
  fastest.image = {};
  for (int i = 1; i < frames; ++i) {
    frame = RenderScene(renderer, scene, meshes, fits);
    frame_ms = std::min(frame_ms, frame.cpu_ms);
    if (frame.gpu_ms < fastest.gpu_ms) {
      fastest = frame;
      fastest.image = {};
    }
  }
  figures["frames"] = frames;
  figures["frame_ms"] = frame_ms;
  figures["gpu_ms"] = fastest.gpu_ms;
  figures["shadow_gpu_ms"] = fastest.shadow_gpu_ms;
  figures["cloth_gpu_ms"] = fastest.cloth_gpu_ms;
  figures["shading_pass"] = frame.compute_pass ? "compute" : "fragment";
  if (frame.compute_pass) figures["shaded_in_place"] = frame.shaded_in_place;
  figures["device"] = DeviceJson(context->info());
  return std::move(frame.image);
}

// Renders knit cloth as volumetric yarn, building each distinct knit fabric's
// lumislices in this process first.
Image RenderLumislice(const v1::SceneSpec& scene, const std::vector<SceneMesh>& meshes, const GlFlags& gl,
                      int frames, nlohmann::json& figures) {
  const SceneLumislices built = BuildSceneLumislices(meshes, LumisliceSettings());
  const std::vector<const YarnLumislices*>& yarns = built.per_mesh;
  figures["precompute_seconds"] = built.seconds;
  const auto context = MakeContext(gl);
  LumisliceRenderer renderer(*context);
  LumisliceFrame frame = renderer.Render(scene, meshes, yarns);
  figures["first_frame_ms"] = frame.rendered.cpu_ms;
  double frame_ms = frame.rendered.cpu_ms, gpu_ms = frame.rendered.gpu_ms;
  for (int i = 1; i < frames; ++i) {
    frame = renderer.Render(scene, meshes, yarns);
    frame_ms = std::min(frame_ms, frame.rendered.cpu_ms);
    gpu_ms = std::min(gpu_ms, frame.rendered.gpu_ms);
  }
  figures["method"] = "lumislice";
  figures["frames"] = frames;
  figures["frame_ms"] = frame_ms;
  figures["gpu_ms"] = gpu_ms;
  figures["segments"] = frame.segments;
  figures["slices"] = frame.slices;
  figures["segments_per_level"] = frame.segments_per_level;
  figures["device"] = DeviceJson(context->info());
  return std::move(frame.rendered.image);
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
    std::string scene, out, method, level_mode, texel_filter, shading_rate, shading_pass, fabric_cache;
    std::optional<float> lod_bias;
    int frames = 1;
    GlFlags gl;
  };
  auto options = std::make_shared<Options>();
  auto* command = app.add_subcommand("render", "Render a scene to an image (.png sRGB or .exr linear)");
  command->add_option("scene", options->scene, "Scene spec file (JSON); OBJ paths are relative to it")->required();
  command->add_option("--out,-o", options->out, "Output image")->required();
  command->add_option("--method", options->method,
                      "reference, lumislice (knit cloth as volumetric yarn on the GPU), or a fabric method for "
                      "every cloth object on the GPU: " + MethodNames() +
                          " (default: the scene's render.method and each object's precompute.method)")
      ->check([](const std::string& name) {
        return name == "reference" || name == "lumislice" || MethodNamed(name)
                   ? std::string()
                   : "not reference, lumislice, " + MethodNames();
      });
  command->add_option("--level-mode", options->level_mode, "svbrdf level mode (default: the scene's render.level_mode)")
      ->check(CLI::IsMember({"none", "nearest", "trilinear", "anisotropic"}));
  command->add_option("--texel-filter", options->texel_filter,
                      "svbrdf texel filter (default: the scene's render.texel_filter)")
      ->check(CLI::IsMember({"nearest", "bilinear"}));
  command->add_option("--lod-bias", options->lod_bias,
                      "levels added to the footprint's, below 0 finer (default: the scene's render.lod_bias)");
  command->add_option("--shading-rate", options->shading_rate,
                      "cloth shaded once per pixel or once per MSAA sample (default: the scene's render.shading_rate)")
      ->check(CLI::IsMember({"pixel", "sample"}));
  command->add_option("--shading-pass", options->shading_pass,
                      "cloth shaded in its fragment shader or in a compute pass over G-buffers (default: the "
                      "scene's render.shading_pass)")
      ->check(CLI::IsMember({"fragment", "compute"}));
  command->add_option("--frames", options->frames,
                      "svbrdf: render this many frames and report the fastest (the first compiles and allocates)")
      ->check(CLI::Range(1, 1000));
  command->add_option("--fabric-cache", options->fabric_cache,
                      "Directory of fabric assets by cache key: svbrdf loads a fabric found there and stores "
                      "one it had to precompute");
  AddGlFlags(command, &options->gl);
  return {command, [&flags, options] {
            FormatFromPath(options->out);  // reject a bad extension before any work
            v1::SceneSpec scene = LoadSpecFile<v1::SceneSpec>(options->scene, "scene");
            if (options->method == "reference") {
              scene.mutable_render()->set_method(v1::RENDER_METHOD_REFERENCE);
            } else if (options->method == "lumislice") {
              scene.mutable_render()->set_method(v1::RENDER_METHOD_LUMISLICE);
            } else if (!options->method.empty()) {
              scene.mutable_render()->set_method(v1::RENDER_METHOD_SVBRDF);
              const v1::FabricMethod method = MethodNamed(options->method)->id();
              for (v1::SceneObject& object : *scene.mutable_objects()) {
                if (object.has_fabric()) object.mutable_fabric()->mutable_precompute()->set_method(method);
              }
            }
            v1::RenderSettings& render = *scene.mutable_render();
            if (!options->level_mode.empty()) {
              v1::LevelMode mode = v1::LEVEL_MODE_UNSPECIFIED;
              v1::LevelMode_Parse(EnumName("LEVEL_MODE_", options->level_mode), &mode);
              render.set_level_mode(mode);
            }
            if (!options->texel_filter.empty()) {
              v1::TexelFilter filter = v1::TEXEL_FILTER_UNSPECIFIED;
              v1::TexelFilter_Parse(EnumName("TEXEL_FILTER_", options->texel_filter), &filter);
              render.set_texel_filter(filter);
            }
            if (options->lod_bias) render.set_lod_bias(*options->lod_bias);  // validated with the scene
            if (!options->shading_rate.empty()) {
              v1::ShadingRate rate = v1::SHADING_RATE_UNSPECIFIED;
              v1::ShadingRate_Parse(EnumName("SHADING_RATE_", options->shading_rate), &rate);
              render.set_shading_rate(rate);
            }
            if (!options->shading_pass.empty()) {
              v1::ShadingPass pass = v1::SHADING_PASS_UNSPECIFIED;
              v1::ShadingPass_Parse(EnumName("SHADING_PASS_", options->shading_pass), &pass);
              render.set_shading_pass(pass);
            }
            scene = WithDefaults(scene);
            ValidateOrThrow(scene);
            const auto meshes =
                BuildSceneGeometry(scene, FileMeshResolver(std::filesystem::path(options->scene).parent_path()));
            const v1::RenderMethod method = scene.render().method();
            nlohmann::json figures = {{"out", options->out}, {"method", "reference"}};
            const Image image =
                method == v1::RENDER_METHOD_REFERENCE ? RenderReference(scene, meshes, figures)
                : method == v1::RENDER_METHOD_LUMISLICE
                    ? RenderLumislice(scene, meshes, options->gl, options->frames, figures)
                    : RenderGpu(scene, meshes, options->gl, options->fabric_cache, options->frames, figures);
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
