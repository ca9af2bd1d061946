// The worker's job execution without the RPC around it: one EGL context, a
// precompute to asset files and back, a render to an encoded frame.

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <set>

#include "core/image/image.h"
#include "core/render/fabric_preview.h"
#include "core/spec/defaults.h"
#include "core/spec/fabric_key.h"
#include "core/util/error.h"
#include "core/util/file_io.h"
#include "tests/server/tiny_specs.h"
#include "worker/job_runner.h"

namespace loom::worker {
namespace {

v1::PrecomputeJob TinyPrecompute() {
  v1::PrecomputeJob job;
  *job.mutable_fabric() = server::KnitFabric();
  *job.mutable_settings() = server::TinySettings();
  return job;
}

// A frame's file decoded (through a temporary file named like it).
Image Decoded(const NamedFile& frame) {
  const auto path = std::filesystem::temp_directory_path() / ("job-runner-test-" + std::to_string(::getpid()) + "-" + frame.name);
  WriteFileAtomic(path, frame.bytes);
  Image image = ReadImage(path);
  std::filesystem::remove(path);
  return image;
}

TEST(JobRunnerTest, PrecomputeGivesTheAssetFilesAndRenderUsesThem) {
  JobRunner runner(gl::DefaultContextOptions());
  const std::string key = FabricKey(server::KnitFabric(), server::TinySettings());
  double last_fraction = 0.0;
  const std::vector<NamedFile> files =
      runner.Precompute(TinyPrecompute(), key, [&](double fraction, std::string_view) { last_fraction = fraction; });
  std::set<std::string> names;
  for (const NamedFile& file : files) names.insert(file.name);
  EXPECT_EQ(names, server::TinyPrecomputeFiles());
  EXPECT_DOUBLE_EQ(last_fraction, 1.0);

  // The preview: the fabric's sphere, lit, over about half the picture.
  const auto preview =
      std::find_if(files.begin(), files.end(), [](const NamedFile& f) { return f.name == kFabricPreviewFile; });
  const Image picture = Decoded(*preview);
  ASSERT_EQ(picture.width, kFabricPreviewPixels);
  ASSERT_EQ(picture.height, kFabricPreviewPixels);
  const v1::Rgb background =
      WithDefaults(FabricPreviewScene(server::KnitFabric(), server::TinySettings())).background();
  int covered = 0;
  double sum = 0.0;
  for (int y = 0; y < picture.height; ++y) {
    for (int x = 0; x < picture.width; ++x) {
      if (std::abs(picture.at(x, y, 0) - background.r()) < 1e-3f) continue;
      ++covered;
      sum += picture.at(x, y, 0);
    }
  }
  const double coverage = static_cast<double>(covered) / (picture.width * picture.height);
  EXPECT_GT(coverage, 0.35);
  EXPECT_LT(coverage, 0.75);
  EXPECT_GT(sum / covered, 0.05);

  const std::unique_ptr<FabricAsset> asset = runner.ReadAsset(files);
  v1::RenderJob render;
  *render.mutable_scene() = server::TinyScene(40, 30);
  render.mutable_scene()->mutable_render()->clear_format();  // unspecified: PNG
  const NamedFile frame = runner.Render(render, FileMeshResolver("."), {{key, asset.get()}});
  EXPECT_EQ(frame.name, "frame.png");
  const Image image = Decoded(frame);
  EXPECT_EQ(image.width, 40);
  EXPECT_EQ(image.height, 30);
}

// A lumislice render needs no fitted fabric: the worker builds the knit's lumislices.
TEST(JobRunnerTest, ALumisliceRenderBuildsItsOwnTables) {
  JobRunner runner(gl::DefaultContextOptions());
  v1::RenderJob render;
  *render.mutable_scene() = server::TinyScene(48, 36);
  render.mutable_scene()->mutable_render()->set_method(v1::RENDER_METHOD_LUMISLICE);
  const NamedFile frame = runner.Render(render, FileMeshResolver("."), {});
  EXPECT_EQ(frame.name, "frame.exr");
  const Image image = Decoded(frame);
  ASSERT_EQ(image.width, 48);
  const v1::Rgb background = WithDefaults(server::TinyScene(48, 36)).background();
  int yarn = 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) yarn += std::abs(image.at(x, y, 0) - background.r()) > 0.02f ? 1 : 0;
  }
  EXPECT_GT(yarn, 48 * 36 / 10);
}

TEST(JobRunnerTest, ThrowingFromProgressCancelsAPrecompute) {
  JobRunner runner(gl::DefaultContextOptions());
  struct Cancelled {};
  EXPECT_THROW(runner.Precompute(TinyPrecompute(), "key", [](double, std::string_view) { throw Cancelled{}; }),
               Cancelled);
}

TEST(JobRunnerTest, ARenderWithoutItsFabricIsRefusedNamingTheObject) {
  JobRunner runner(gl::DefaultContextOptions());
  v1::RenderJob render;
  *render.mutable_scene() = server::TinyScene(8, 8);
  try {
    runner.Render(render, FileMeshResolver("."), {});
    FAIL() << "rendered without a fitted fabric";
  } catch (const Error& error) {
    EXPECT_EQ(error.code(), ErrorCode::kFailedPrecondition);
    EXPECT_NE(std::string(error.what()).find("cloth"), std::string::npos) << error.what();
  }
}

// A directory named like a worker's scratch directory, with a file in it.
std::filesystem::path FakeScratch(pid_t pid, const std::string& suffix) {
  const auto path = std::filesystem::temp_directory_path() / ("loom-worker-" + std::to_string(pid) + "-" + suffix);
  std::filesystem::create_directories(path);
  WriteFileAtomic(path / "lut.exr", "left over");
  return path;
}

TEST(JobRunnerTest, ScratchDirectoryIsRemovedAtExitAndDeadWorkersOnesAtStart) {
  // A process that is gone (reaped, so its pid names no process) left its directory.
  const pid_t dead = fork();
  ASSERT_GE(dead, 0);
  if (dead == 0) _exit(0);
  ASSERT_EQ(waitpid(dead, nullptr, 0), dead);
  const auto stale = FakeScratch(dead, "0");
  const auto live = FakeScratch(::getpid(), "live-test");  // this process is alive: kept

  std::filesystem::path scratch;
  {
    JobRunner runner(gl::DefaultContextOptions());
    scratch = runner.scratch_directory();
    EXPECT_TRUE(std::filesystem::is_directory(scratch));
    EXPECT_FALSE(std::filesystem::exists(stale));
    EXPECT_TRUE(std::filesystem::exists(live / "lut.exr"));
    // A failing step leaves nothing behind either.
    EXPECT_THROW(runner.ReadAsset({{"lut.exr", "not an EXR"}}), Error);
    EXPECT_TRUE(std::filesystem::is_empty(scratch));
  }
  EXPECT_FALSE(std::filesystem::exists(scratch));
  std::filesystem::remove_all(live);
}

}  // namespace
}  // namespace loom::worker
