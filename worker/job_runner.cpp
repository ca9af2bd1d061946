#include "worker/job_runner.h"

#include <unistd.h>

#include <atomic>

#include "core/fit/fabric_asset.h"
#include "core/image/image.h"
#include "core/render/reference_renderer.h"
#include "core/spec/defaults.h"
#include "core/spec/validate.h"
#include "core/util/error.h"
#include "core/util/file_io.h"

namespace loom::worker {
namespace {

// Distinct per runner in one process (the server's local workers share a pid).
std::filesystem::path MakeScratchDirectory() {
  static std::atomic<int> next{0};
  const auto path = std::filesystem::temp_directory_path() /
                    ("loom-worker-" + std::to_string(::getpid()) + "-" + std::to_string(next++));
  std::filesystem::remove_all(path);
  std::filesystem::create_directories(path);
  return path;
}

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
      renderer_(std::make_unique<SvbrdfRenderer>(*context_)),
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
  const FittedFabric fit = PrecomputeFabric(job.fabric(), job.settings(), progress);
  const auto directory = NewScratchPath("asset");
  WriteFabricAsset(fit, job.settings(), fabric_key, directory);
  std::vector<NamedFile> files = ReadDirectory(directory);
  std::filesystem::remove_all(directory);
  return files;
}

FittedFabric JobRunner::ReadAsset(const std::vector<NamedFile>& files) {
  const auto directory = NewScratchPath("fabric");
  std::filesystem::create_directories(directory);
  for (const NamedFile& file : files) {
    if (file.name.empty() || file.name.find('/') != std::string::npos) {
      throw Error(ErrorCode::kInvalidArgument, "fabric asset file name '" + file.name + "' is not a plain name");
    }
    WriteFileAtomic(directory / file.name, file.bytes);
  }
  FittedFabric fit = ReadFabricAsset(directory);
  std::filesystem::remove_all(directory);
  return fit;
}

NamedFile JobRunner::Render(const v1::RenderJob& job, const MeshTextResolver& meshes, const FittedFabrics& fits) {
  const v1::SceneSpec scene = WithDefaults(job.scene());
  ValidateOrThrow(scene);
  const std::vector<SceneMesh> geometry = BuildSceneGeometry(scene, meshes);
  const Image image = scene.render().method() == v1::RENDER_METHOD_REFERENCE
                          ? ReferenceRenderer().Render(scene, geometry).image
                          : RenderScene(*renderer_, scene, geometry, fits).image;
  const bool exr = scene.render().format() == v1::IMAGE_FORMAT_EXR;
  const std::string name = exr ? "frame.exr" : "frame.png";
  const auto path = NewScratchPath("frame") / name;
  std::filesystem::create_directories(path.parent_path());
  WriteImage(image, path);
  NamedFile file{name, ReadFile(path)};
  std::filesystem::remove_all(path.parent_path());
  return file;
}

}  // namespace loom::worker
