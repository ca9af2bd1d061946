#include "server/store/own_temp_dir.h"

#include <gtest/gtest.h>

#include <csignal>
#include <memory>
#include <vector>

#include "core/util/file_io.h"
#include "store_test_util.h"

namespace loom::server {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> Entries(const fs::path& dir) {
  std::vector<fs::path> entries;
  for (const auto& entry : fs::directory_iterator(dir)) entries.push_back(entry.path());
  return entries;
}

TEST(OwnTempDir, EachProcessGetsItsOwnAndADeadOnesIsRemoved) {
  const fs::path root = FreshDataDir() / "tmp";
  fs::path dead;
  EXPECT_EXIT(
      {
        const OwnTempDir mine(root);
        WriteFileAtomic(mine.path() / "upload-0", "half an upload");
        std::raise(SIGKILL);  // no destructor: the directory stays, its lock goes
      },
      ::testing::KilledBySignal(SIGKILL), "");
  ASSERT_EQ(Entries(root).size(), 1u);
  dead = Entries(root).front();
  EXPECT_TRUE(fs::exists(dead / "upload-0"));

  const auto first = std::make_unique<OwnTempDir>(root);
  EXPECT_FALSE(fs::exists(dead));
  WriteFileAtomic(first->path() / "upload-0", "in flight");
  {
    const OwnTempDir second(root);  // another server on the same volume
    EXPECT_NE(second.path(), first->path());
    EXPECT_TRUE(fs::exists(first->path() / "upload-0"));
    EXPECT_EQ(Entries(root).size(), 2u);
  }
  EXPECT_EQ(Entries(root), std::vector<fs::path>{first->path()});  // the second removed its own
}

TEST(OwnTempDir, LooseFilesAndDirectoriesWithoutALockAreLeftovers) {
  const fs::path root = FreshDataDir() / "tmp";
  WriteFileAtomic(root / "upload-123-0", "from before directories of their own");
  WriteFileAtomic(root / "nested" / "upload-123-1", "no lock file");
  const OwnTempDir mine(root);
  EXPECT_EQ(Entries(root), std::vector<fs::path>{mine.path()});
  EXPECT_EQ(mine.path().parent_path(), root);
}

TEST(OwnTempDir, ARootThatCannotBeMadeIsUnavailableNamingIt) {
  const fs::path file = FreshDataDir() / "a-file";
  WriteFileAtomic(file, "not a directory");
  EXPECT_LOOM_ERROR(OwnTempDir{file / "tmp"}, ErrorCode::kUnavailable, (file / "tmp").string());
}

}  // namespace
}  // namespace loom::server
