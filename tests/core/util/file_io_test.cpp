#include "core/util/file_io.h"

#include <gtest/gtest.h>

#include "core/util/error.h"

namespace loom {
namespace {

TEST(FileIo, AtomicWriteReplacesWholeFileAndLeavesNoTemp) {
  const auto dir = std::filesystem::path(::testing::TempDir()) / "loom_file_io_test";
  std::filesystem::remove_all(dir);
  const auto path = dir / "nested" / "file.bin";
  WriteFileAtomic(path, "first version, longer");
  WriteFileAtomic(path, "second");
  EXPECT_EQ(ReadFile(path), "second");
  int entries = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(path.parent_path())) ++entries;
  EXPECT_EQ(entries, 1);
}

TEST(FileIo, MissingFileIsNotFoundAndNamesThePath) {
  try {
    ReadFile("/nonexistent/loom/spec.json");
    FAIL();
  } catch (const Error& error) {
    EXPECT_EQ(error.code(), ErrorCode::kNotFound);
    EXPECT_NE(std::string(error.what()).find("/nonexistent/loom/spec.json"), std::string::npos);
  }
}

}  // namespace
}  // namespace loom
