#include "worker/job_runner.h"

#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <charconv>
#include <string_view>

#include "core/animate/cloth_sequence_io.h"
#include "core/image/image.h"
#include "core/methods/fabric_method.h"
#include "core/render/fabric_preview.h"
#include "core/render/reference_renderer.h"
#include "core/spec/defaults.h"
#include "core/spec/validate.h"
#include "core/util/error.h"
#include "core/util/file_io.h"

namespace loom::worker {
namespace {

constexpr std::string_view kScratchPrefix = "loom-worker-";

// Removes the scratch directories under `parent` whose process no longer exists
// (SIGKILLed, crashed). A live process's, or one that is not ours to signal, stays.
void SweepStaleScratchDirectories(const std::filesystem::path& parent) {
  std::error_code ignored;
  for (const auto& entry : std::filesystem::directory_iterator(parent, ignored)) {
    const std::string name = entry.path().filename().string();
    if (!name.starts_with(kScratchPrefix)) continue;
    const char* digits = name.data() + kScratchPrefix.size();
    const char* end = name.data() + name.size();
    pid_t pid = 0;
    const auto [after, error] = std::from_chars(digits, end, pid);
    if (error != std::errc() || after == end || *after != '-' || pid <= 0) continue;
    if (::kill(pid, 0) == 0 || errno != ESRCH) continue;
    std::filesystem::remove_all(entry.path(), ignored);
  }
}

// Distinct per runner in one process (the server's local workers share a pid).
std::filesystem::path MakeScratchDirectory() {
  static std::atomic<int> next{0};
  const auto parent = std::filesystem::temp_directory_path();
  SweepStaleScratchDirectories(parent);
  const auto path = parent / (std::string(kScratchPrefix) + std::to_string(::getpid()) + "-" + std::to_string(next++));
  std::filesystem::remove_all(path);
  std::filesystem::create_directories(path);
  return path;
}

// A job step's directory under the scratch directory, removed however the step ends.
class StepDirectory {
 public:
  explicit StepDirectory(std::filesystem::path path) : path_(std::move(path)) {
    std::filesystem::create_directories(path_);
  }
  ~StepDirectory() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  StepDirectory(const StepDirectory&) = delete;
  StepDirectory& operator=(const StepDirectory&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

std::vector<NamedFile> ReadDirectory(const std::filesystem::path& directory) {
  std::vector<NamedFile> files;
  for (const auto& entry : std::filesystem::directory_iterator(directory)) {
    files.push_back({entry.path().filename().string(), ReadFile(entry.path())});
  }
  return files;
}

}  // namespace

JobRunner::JobRunner(const gl::ContextOptions& options)
    : context_(gl::EglContext::Create(options)),
      renderer_(std::make_unique<GpuRenderer>(*context_)),
      scratch_(MakeScratchDirectory()) {}

JobRunner::~JobRunner() {
  std::error_code ignored;
  std::filesystem::remove_all(scratch_, ignored);
}

std::filesystem::path JobRunner::NewScratchPath(const std::string& stem) {
  return scratch_ / (stem + "-" + std::to_string(next_scratch_++));
}

std::vector<NamedFile> JobRunner::Precompute(const v1::PrecomputeJob& job, const std::string& fabric_key,
                                             const PrecomputeProgress& progress) {
  const std::unique_ptr<FabricAsset> asset = PrecomputeAsset(job.fabric(), job.settings(), progress);
  const StepDirectory directory(NewScratchPath("asset"));
  asset->Write(job.settings(), fabric_key, directory.path());
  WriteImage(RenderFabricPreview(*renderer_, job.fabric(), job.settings(), *asset),
             directory.path() / kFabricPreviewFile);
  WriteAssetPictures(*asset, directory.path());
  return ReadDirectory(directory.path());
}

std::unique_ptr<FabricAsset> JobRunner::ReadAsset(const std::vector<NamedFile>& files) {
  const StepDirectory directory(NewScratchPath("fabric"));
  for (const NamedFile& file : files) {
    if (file.name.empty() || file.name.find('/') != std::string::npos) {
      throw Error(ErrorCode::kInvalidArgument, "fabric asset file name '" + file.name + "' is not a plain name");
    }
    WriteFileAtomic(directory.path() / file.name, file.bytes);
  }
  return ReadAnyFabricAsset(directory.path());
}

NamedFile JobRunner::Render(const v1::RenderJob& job, const MeshTextResolver& meshes, const FabricAssets& assets,
                            const ReferenceProgress& progress) {
  const v1::SceneSpec scene = WithDefaults(job.scene());
  ValidateOrThrow(scene);
  const std::vector<SceneMesh> geometry = BuildSceneGeometry(scene, meshes, &sequences_);
  Image image;
  switch (scene.render().method()) {
    case v1::RENDER_METHOD_REFERENCE:
      image = ReferenceRenderer().Render(scene, geometry, progress).image;
      break;
    case v1::RENDER_METHOD_LUMISLICE: {
      if (!lumislice_renderer_) lumislice_renderer_ = std::make_unique<LumisliceRenderer>(*context_);
      const SceneLumislices lumislices = BuildSceneLumislices(geometry, LumisliceSettings(), &lumislice_cache_);
      image = lumislice_renderer_->Render(scene, geometry, lumislices.per_mesh).rendered.image;
      break;
    }
    default:
      image = RenderScene(*renderer_, scene, geometry, assets).image;
      break;
  }
  const bool exr = scene.render().format() == v1::IMAGE_FORMAT_EXR;
  const std::string name = exr ? "frame.exr" : "frame.png";
  const StepDirectory directory(NewScratchPath("frame"));
  WriteImage(image, directory.path() / name);
  return {name, ReadFile(directory.path() / name)};
}

NamedFile JobRunner::Animate(const v1::AnimateJob& job, const MeshTextResolver& meshes,
                             const PrecomputeProgress& progress) {
  const animate::ClothAnimation animation = animate::RunAnimation(
      job.animation(),
      [&](size_t done, size_t total) {
        progress(static_cast<double>(done) / static_cast<double>(total),
                 "simulation: frame " + std::to_string(done) + "/" + std::to_string(total));
      },
      0, meshes);
  const StepDirectory directory(NewScratchPath("sequence"));
  const std::filesystem::path path = directory.path() / "sequence.glb";
  animate::WriteGltfSequence(animate::ClothSequence(animation), path, animate::SolidTracks(animation));
  return {path.filename().string(), ReadFile(path)};
}

}  // namespace loom::worker
