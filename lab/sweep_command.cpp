// loom-lab sweep: the speed-versus-accuracy measurement (issue 7, DESIGN.md
// "Measurement protocol"). For every configuration × bench scene of a grid file
// (lab/sweep_grid.h) one CSV row: precompute seconds and asset bytes, frame time
// (CPU wall, GPU), and error against a high-sample reference of the same scene
// (RMSE, PSNR, 1 − SSIM) plus flicker under a sub-pixel camera move.
//
// Reuse across rows and runs, all under --out:
//   <grid>.csv          the rows; a rerun skips the rows present (resume)
//   ground_truth/*.exr  the reference of each scene at the grid's ground-truth spp
//   fabrics/<key>/      each distinct (fabric, precompute settings) fitted once
//                       (lab/fabric_cache.h), whatever scenes and render settings use it

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <glm/glm.hpp>
#include <map>

#include "core/image/image.h"
#include "core/metrics/image_metrics.h"
#include "core/plan/fabric_kind.h"
#include "core/plan/screen_footprint.h"
#include "core/render/lumislice_renderer.h"
#include "core/render/reference_renderer.h"
#include "core/render/scene_render.h"
#include "core/spec/defaults.h"
#include "core/spec/spec_json.h"
#include "core/util/cli_main.h"
#include "core/util/error.h"
#include "core/util/file_io.h"
#include "core/util/stopwatch.h"
#include "lab/fabric_cache.h"
#include "lab/lab_command.h"
#include "lab/sweep_grid.h"
#include "lab/sweep_results.h"

namespace loom::lab {
namespace {

const std::vector<std::string> kColumns = {
    "configuration", "scene", "method", "method_settings", "fabric", "view", "distance", "tile_pixels",
    "footprint_pixels", "fabric_kind",
    "spatial_resolution", "view_directions", "light_directions", "lobes", "lookup_table",
    "supersampling", "sampling_plane", "seed", "level_mode", "texel_filter", "msaa_samples", "lod_bias", "shading_rate", "reference_samples",
    "precompute_seconds", "precompute_cpu_seconds", "asset_bytes", "frame_ms", "gpu_ms",
    "rmse", "psnr_db", "perceptual_error", "flicker", "load_average"};

// The ground truth is drawn with its own seed, so a reference row at the same
// sample count is not compared with its own noise.
constexpr uint64_t kGroundTruthSeed = 0x9e3779b97f4a7c15ull;

std::string Number(double value) {
  if (!std::isfinite(value)) return std::isnan(value) ? "nan" : (value > 0 ? "inf" : "-inf");
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", value);
  return text;
}

double LoadAverage() {
  double load[1] = {0.0};
  return getloadavg(load, 1) == 1 ? load[0] : NAN;
}

// `scene` with its camera moved `pixels` pixels to the right (position and target
// together), as a pan by a sub-pixel step shows aliasing as flicker.
v1::SceneSpec Panned(v1::SceneSpec scene, double pixels) {
  if (pixels == 0.0) return scene;
  const v1::Camera& camera = scene.camera();
  const auto vec = [](const v1::Vec3& v) { return glm::dvec3(v.x(), v.y(), v.z()); };
  const glm::dvec3 position = vec(camera.position()), target = vec(camera.target());
  const glm::dvec3 forward = glm::normalize(target - position);
  const glm::dvec3 right = glm::normalize(glm::cross(forward, vec(camera.up())));
  const double view_height = camera.projection() == v1::PROJECTION_ORTHOGRAPHIC
                                 ? camera.ortho_height()
                                 : 2.0 * glm::length(target - position) *
                                       std::tan(glm::radians(static_cast<double>(camera.fov_y_degrees())) / 2.0);
  const glm::dvec3 step = right * (pixels * view_height / scene.render().height());
  const auto set = [](v1::Vec3* v, const glm::dvec3& p) {
    v->set_x(static_cast<float>(p.x));
    v->set_y(static_cast<float>(p.y));
    v->set_z(static_cast<float>(p.z));
  };
  set(scene.mutable_camera()->mutable_position(), position + step);
  set(scene.mutable_camera()->mutable_target(), target + step);
  return scene;
}

struct Frames {
  std::vector<Image> images;  // images[k]: the camera panned by k · shift
  std::vector<double> cpu_ms, gpu_ms;
};

// The largest on-screen tile as the planner measures it (core/plan/screen_footprint.h):
// the figure its footprint classes are distilled by.
double FootprintPixels(const v1::SceneSpec& scene) {
  const auto meshes = BuildSceneGeometry(scene, FileMeshResolver({}));
  double largest = 0.0;
  for (const SceneMesh& mesh : meshes) largest = std::max(largest, MeasureTileFootprint(scene, mesh).largest_pixels);
  return largest;
}

// Frame times are the best of the flicker frames: the first pays for warm-up
// (shader variants, texture upload) and a loaded machine only ever adds time.
double Fastest(const std::vector<double>& values) {
  return values.empty() ? NAN : *std::min_element(values.begin(), values.end());
}

class Sweep {
 public:
  Sweep(SweepGrid grid, std::filesystem::path out, GlFlags gl)
      : grid_(std::move(grid)), out_(std::move(out)), gl_(gl),
        results_(out_ / (grid_.name + ".csv"), kColumns) {}

  struct Outcome {
    size_t measured = 0, failed = 0;
  };

  // Measures every row not yet in the CSV. A row that fails (an Error: a setting
  // the device cannot render, a fit that throws) is reported and left out of the
  // CSV, so the others are still measured and a rerun retries it.
  Outcome Run() {
    size_t pending = 0;
    for (const auto& configuration : grid_.configurations) {
      for (const auto& scene : grid_.scenes) {
        if (Pending(configuration, scene)) ++pending;
      }
    }
    std::fprintf(stderr, "sweep %s: %zu rows to measure, %zu already in %s\n", grid_.name.c_str(), pending,
                 results_.size(), (out_ / (grid_.name + ".csv")).c_str());
    total_ = pending;
    for (const auto& configuration : grid_.configurations) {
      if (configuration.method == v1::RENDER_METHOD_REFERENCE) {
        for (const auto& scene : grid_.scenes) MeasureReference(configuration, scene);
      } else if (configuration.method == v1::RENDER_METHOD_LUMISLICE) {
        for (const auto& scene : grid_.scenes) {
          if (Pending(configuration, scene)) Guarded(configuration, {&scene}, [&] { MeasureLumislice(configuration, scene); });
        }
      } else {
        MeasureSvbrdf(configuration);
      }
    }
    return {done_, failed_};
  }

 private:
  bool Pending(const SweepConfiguration& configuration, const BenchScene& scene) const {
    return grid_.Applies(configuration, scene) && !results_.Contains(configuration.name, scene.name);
  }

  // Fits each fabric the configuration needs once and renders every pending scene
  // with it.
  void MeasureSvbrdf(const SweepConfiguration& configuration) {
    std::map<std::string, std::vector<const BenchScene*>> by_fabric;
    std::map<std::string, SceneFabric> fabrics;
    std::vector<std::string> order;
    for (const auto& scene : grid_.scenes) {
      if (!Pending(configuration, scene)) continue;
      for (const SceneFabric& fabric : SceneFabrics(WithDefaults(ConfiguredScene(configuration, scene)))) {
        if (!fabrics.contains(fabric.key)) order.push_back(fabric.key);
        fabrics.emplace(fabric.key, fabric);
        by_fabric[fabric.key].push_back(&scene);
      }
    }
    for (const std::string& key : order) {
      CachedFabric cached;
      if (!Guarded(configuration, by_fabric.at(key), [&] { cached = LoadOrPrecompute(fabrics.at(key), out_ / "fabrics"); })) {
        continue;
      }
      const FabricAssets fits = {{key, cached.asset.get()}};
      for (const BenchScene* scene : by_fabric.at(key)) {
        Guarded(configuration, {scene}, [&] { MeasureSvbrdfScene(configuration, *scene, cached, fits); });
      }
    }
  }

  void MeasureSvbrdfScene(const SweepConfiguration& configuration, const BenchScene& scene,
                          const CachedFabric& cached, const FabricAssets& fits) {
    const v1::SceneSpec configured = WithDefaults(ConfiguredScene(configuration, scene));
    Frames frames;
    for (int k = 0; k < grid_.flicker_frames; ++k) {
      const v1::SceneSpec panned = Panned(configured, k * grid_.flicker_shift_pixels);
      const auto meshes = BuildSceneGeometry(panned, FileMeshResolver({}));
      RenderedFrame frame = RenderScene(Renderer(), panned, meshes, fits);
      frames.images.push_back(std::move(frame.image));
      frames.cpu_ms.push_back(frame.cpu_ms);
      frames.gpu_ms.push_back(frame.gpu_ms);
    }
    Record(configuration, scene, configured, frames, cached);
  }

  // Builds the lumislices of the scene's knit cloth once per fabric (its time and
  // size are the row's precompute and asset figures) and renders the scene with them.
  void MeasureLumislice(const SweepConfiguration& configuration, const BenchScene& scene) {
    const v1::SceneSpec configured = WithDefaults(ConfiguredScene(configuration, scene));
    const v1::FabricSpec fabric = WithDefaults(configured.objects(0).fabric().fabric());
    auto [at, inserted] = lumislices_.try_emplace(fabric.SerializeAsString());
    if (inserted) {
      const Stopwatch stopwatch;
      at->second.slices = BuildFabricLumislices(fabric, LumisliceSettings());
      at->second.seconds = stopwatch.Seconds();
    }
    CachedFabric built;
    built.precompute_seconds = at->second.seconds;
    built.precompute_cpu_seconds = NAN;
    for (const Lumislice& slice : at->second.slices) built.asset_bytes += slice.StoredBytes();
    Frames frames;
    for (int k = 0; k < grid_.flicker_frames; ++k) {
      const v1::SceneSpec panned = Panned(configured, k * grid_.flicker_shift_pixels);
      const auto meshes = BuildSceneGeometry(panned, FileMeshResolver({}));
      std::vector<const YarnLumislices*> yarns(meshes.size(), nullptr);
      for (size_t i = 0; i < meshes.size(); ++i) {
        if (meshes[i].object->has_fabric()) yarns[i] = &at->second.slices;
      }
      if (!lumislice_renderer_) lumislice_renderer_ = std::make_unique<LumisliceRenderer>(Context());
      LumisliceFrame frame = lumislice_renderer_->Render(panned, meshes, yarns);
      frames.images.push_back(std::move(frame.rendered.image));
      frames.cpu_ms.push_back(frame.rendered.cpu_ms);
      frames.gpu_ms.push_back(frame.rendered.gpu_ms);
    }
    Record(configuration, scene, configured, frames, built);
  }

  // Runs `measure`; on an Error counts `scenes` as failed rows and says why.
  template <typename Measure>
  bool Guarded(const SweepConfiguration& configuration, const std::vector<const BenchScene*>& scenes,
               Measure&& measure) {
    try {
      measure();
      return true;
    } catch (const Error& e) {
      failed_ += scenes.size();
      for (const BenchScene* scene : scenes) {
        std::fprintf(stderr, "[failed] %s %s: %s\n", configuration.name.c_str(), scene->name.c_str(), e.what());
      }
      return false;
    }
  }

  void MeasureReference(const SweepConfiguration& configuration, const BenchScene& scene) {
    if (!Pending(configuration, scene)) return;
    Guarded(configuration, {&scene}, [&] { MeasureReferenceScene(configuration, scene); });
  }

  void MeasureReferenceScene(const SweepConfiguration& configuration, const BenchScene& scene) {
    const v1::SceneSpec configured = WithDefaults(ConfiguredScene(configuration, scene));
    Frames frames;
    for (int k = 0; k < grid_.flicker_frames; ++k) {
      const v1::SceneSpec panned = Panned(configured, k * grid_.flicker_shift_pixels);
      ReferenceFrame frame = reference_.Render(panned, BuildSceneGeometry(panned, FileMeshResolver({})));
      frames.images.push_back(std::move(frame.image));
      frames.cpu_ms.push_back(frame.cpu_ms);
    }
    Record(configuration, scene, configured, frames, CachedFabric{});
  }

  // The reference of `scene` at the grid's ground-truth samples, rendered once
  // and kept under --out.
  const Image& GroundTruth(const BenchScene& scene) {
    if (const auto found = ground_truth_.find(scene.name); found != ground_truth_.end()) return found->second;
    const std::filesystem::path path = out_ / "ground_truth" / (scene.name + ".exr");
    if (!std::filesystem::exists(path)) {
      v1::SceneSpec truth = scene.scene;
      truth.mutable_render()->set_method(v1::RENDER_METHOD_REFERENCE);
      truth.mutable_render()->set_reference_samples(grid_.ground_truth_samples);
      truth.mutable_render()->set_seed(kGroundTruthSeed);
      truth = WithDefaults(truth);
      std::fprintf(stderr, "ground truth %s (%u spp)...\n", scene.name.c_str(), grid_.ground_truth_samples);
      const ReferenceFrame frame = reference_.Render(truth, BuildSceneGeometry(truth, FileMeshResolver({})));
      std::fprintf(stderr, "ground truth %s: %.1f s\n", scene.name.c_str(), frame.cpu_ms / 1e3);
      WriteImage(frame.image, path);
    }
    return ground_truth_.emplace(scene.name, ReadImage(path)).first->second;
  }

  gl::EglContext& Context() {
    if (!context_) context_ = MakeContext(gl_);
    return *context_;
  }

  GpuRenderer& Renderer() {
    if (!renderer_) renderer_ = std::make_unique<GpuRenderer>(Context());
    return *renderer_;
  }

  void Record(const SweepConfiguration& configuration, const BenchScene& scene, const v1::SceneSpec& configured,
              const Frames& frames, const CachedFabric& precomputed) {
    const bool svbrdf = configuration.method == v1::RENDER_METHOD_SVBRDF;
    const bool lumislice = configuration.method == v1::RENDER_METHOD_LUMISLICE;
    const ImageComparison error = CompareImages(frames.images.front(), GroundTruth(scene));
    const double flicker = frames.images.size() >= 2 ? TemporalFlicker(frames.images, 0, 0) : NAN;
    // The settings the cloth was precomputed with (a plan configuration chooses per scene).
    const v1::PrecomputeSettings precompute = WithDefaults(configured.objects(0).fabric().precompute());
    const v1::RenderSettings& render = configured.render();
    const RenderColumns render_columns = SweepRenderColumns(render);
    const auto when_svbrdf = [svbrdf](const std::string& value) { return svbrdf ? value : std::string(); };
    const std::string method =
        svbrdf ? std::string(MethodOf(precompute.method()).name()) : lumislice ? "lumislice" : "reference";
    const std::string own = svbrdf ? MethodOf(precompute.method()).OwnSettings(precompute) : std::string();
    results_.Append({configuration.name, scene.name, method, own, scene.fabric, scene.view,
                     scene.distance, Number(scene.tile_pixels), Number(FootprintPixels(configured)),
                     FabricKindName(ClassifyFabric(configured.objects(0).fabric().fabric())),
                     when_svbrdf(std::to_string(precompute.spatial_resolution())),
                     when_svbrdf(std::to_string(precompute.view_directions())),
                     when_svbrdf(std::to_string(precompute.light_directions())),
                     when_svbrdf(std::to_string(precompute.lobes())),
                     when_svbrdf(precompute.lookup_table() ? "1" : "0"),
                     when_svbrdf(std::to_string(precompute.supersampling())),
                     when_svbrdf(SamplingPlaneColumn(precompute.sampling_plane())),
                     when_svbrdf(std::to_string(precompute.seed())),
                     when_svbrdf(render_columns.level_mode), when_svbrdf(render_columns.texel_filter),
                     when_svbrdf(render_columns.msaa_samples), when_svbrdf(render_columns.lod_bias),
                     when_svbrdf(render_columns.shading_rate),
                     svbrdf || lumislice ? std::string() : std::to_string(render.reference_samples()),
                     Number(precomputed.precompute_seconds), Number(precomputed.precompute_cpu_seconds),
                     std::to_string(precomputed.asset_bytes), Number(Fastest(frames.cpu_ms)),
                     svbrdf || lumislice ? Number(Fastest(frames.gpu_ms)) : std::string(), Number(error.rmse),
                     Number(error.psnr_db), Number(1.0 - error.ssim), Number(flicker), Number(LoadAverage())});
    ++done_;
    std::fprintf(stderr, "[%zu/%zu] %-16s %-24s PSNR %6.2f dB  1-SSIM %.4f  frame %8.1f ms\n", done_, total_,
                 configuration.name.c_str(), scene.name.c_str(), error.psnr_db, 1.0 - error.ssim,
                 Fastest(frames.cpu_ms));
  }

  SweepGrid grid_;
  std::filesystem::path out_;
  GlFlags gl_;
  SweepResults results_;
  ReferenceRenderer reference_;
  std::map<std::string, Image> ground_truth_;
  std::unique_ptr<gl::EglContext> context_;
  std::unique_ptr<GpuRenderer> renderer_;
  std::unique_ptr<LumisliceRenderer> lumislice_renderer_;
  struct BuiltLumislices {
    YarnLumislices slices;
    double seconds = 0.0;
  };
  std::map<std::string, BuiltLumislices> lumislices_;  // by serialised fabric
  size_t done_ = 0, total_ = 0, failed_ = 0;
};

}  // namespace

LabCommand AddSweepCommand(CLI::App& app, const LabFlags& flags) {
  struct Options {
    std::string grid, out, emit_scenes;
    bool list = false;
    GlFlags gl;
  };
  auto options = std::make_shared<Options>();
  auto* command = app.add_subcommand(
      "sweep", "Measure speed against accuracy over a grid of settings and bench scenes (one CSV row per "
               "configuration and scene; resumable)");
  command->add_option("grid", options->grid, "Sweep grid file (e.g. bench/sweep.json)")->required();
  command->add_option("--out,-o", options->out, "Results directory: <grid>.csv, ground truth, fabric cache");
  command->add_flag("--list", options->list, "Print the grid's scenes and configurations, measure nothing");
  command->add_option("--emit-scenes", options->emit_scenes,
                      "Write each of the grid's scenes as a plain scene spec DIR/<scene>.json, measure nothing");
  AddGlFlags(command, &options->gl);
  return {command, [&flags, options] {
            SweepGrid grid = LoadSweepGrid(options->grid);
            if (options->list) {
              nlohmann::json listing = {{"scenes", nlohmann::json::array()}, {"configurations", nlohmann::json::array()}};
              for (const auto& scene : grid.scenes) listing["scenes"].push_back(scene.name);
              for (const auto& configuration : grid.configurations) {
                size_t scenes = 0;
                for (const auto& scene : grid.scenes) scenes += grid.Applies(configuration, scene) ? 1 : 0;
                listing["configurations"].push_back({{"name", configuration.name}, {"scenes", scenes}});
              }
              if (flags.json) {
                PrintJson(listing);
              } else {
                for (const auto& scene : listing["scenes"]) std::printf("scene %s\n", scene.get<std::string>().c_str());
                for (const auto& c : listing["configurations"]) {
                  std::printf("configuration %s (%zu scenes)\n", c["name"].get<std::string>().c_str(),
                              c["scenes"].get<size_t>());
                }
              }
              return 0;
            }
            if (!options->emit_scenes.empty()) {
              for (const auto& scene : grid.scenes) {
                WriteFileAtomic(std::filesystem::path(options->emit_scenes) / (scene.name + ".json"),
                                SpecToJson(scene.scene) + "\n");
              }
              if (flags.json) PrintJson({{"scenes", grid.scenes.size()}, {"directory", options->emit_scenes}});
              else std::printf("wrote %zu scenes to %s\n", grid.scenes.size(), options->emit_scenes.c_str());
              return 0;
            }
            if (options->out.empty()) throw Error(ErrorCode::kInvalidArgument, "--out: required to measure");
            const Stopwatch stopwatch;
            const std::string csv = (std::filesystem::path(options->out) / (grid.name + ".csv")).string();
            Sweep sweep(std::move(grid), options->out, options->gl);
            const Sweep::Outcome outcome = sweep.Run();
            if (flags.json) {
              PrintJson({{"csv", csv},
                         {"measured", outcome.measured},
                         {"failed", outcome.failed},
                         {"seconds", stopwatch.Seconds()}});
            } else {
              std::printf("measured %zu rows in %.1f s into %s; %zu failed\n", outcome.measured,
                          stopwatch.Seconds(), csv.c_str(), outcome.failed);
            }
            // Failed rows are not in the CSV: the sweep is incomplete.
            return outcome.failed == 0 ? 0 : ExitCodeFor(ErrorCode::kInternal);
          }};
}

}  // namespace loom::lab
