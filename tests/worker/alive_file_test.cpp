// The worker's liveness file: its content, its rate limit (with an injected clock,
// no sleeping) and that failing to write it is not the worker's failure.

#include "worker/alive_file.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "core/util/file_io.h"

namespace loom::worker {
namespace {

using namespace std::chrono_literals;

class AliveFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  nlohmann::json Content() const { return nlohmann::json::parse(ReadFile(path_)); }

  const std::filesystem::path dir_ =
      std::filesystem::path(::testing::TempDir()) / ("loom-alive-file-test-" + std::to_string(::getpid()));
  const std::filesystem::path path_ = dir_ / "worker.alive";
  // 2026-11-24 00:00:00 UTC, a whole second.
  std::chrono::system_clock::time_point now_{std::chrono::seconds(1'795'478'400)};
  AliveFile alive_{path_, [this] { return now_; }};
};

TEST_F(AliveFileTest, MarkWritesOneJsonLineWithTimeStateAndPid) {
  alive_.Mark("waiting for work");
  const std::string text = ReadFile(path_);
  ASSERT_FALSE(text.empty());
  EXPECT_EQ(text.find('\n'), text.size() - 1) << text;
  EXPECT_EQ(text.rfind(R"({"unix_time":)", 0), 0u) << text;  // the documented order, time first
  const nlohmann::json content = nlohmann::json::parse(text);
  EXPECT_EQ(content.at("unix_time").get<int64_t>(), 1'795'478'400);
  EXPECT_EQ(content.at("state").get<std::string>(), "waiting for work");
  EXPECT_EQ(content.at("pid").get<int64_t>(), ::getpid());
}

TEST_F(AliveFileTest, TheSameStateIsRewrittenAtMostOnceASecond) {
  alive_.Mark("job 7: render");
  std::filesystem::remove(path_);  // a rewrite would bring it back
  now_ += 999ms;
  alive_.Mark("job 7: render");
  EXPECT_FALSE(std::filesystem::exists(path_));
  now_ += 1ms;
  alive_.Mark("job 7: render");
  ASSERT_TRUE(std::filesystem::exists(path_));
  EXPECT_EQ(Content().at("unix_time").get<int64_t>(), 1'795'478'401);
}

TEST_F(AliveFileTest, AChangedStateIsWrittenAtOnce) {
  alive_.Mark("waiting for work");
  now_ += 10ms;
  alive_.Mark("job 7: render");
  EXPECT_EQ(Content().at("state").get<std::string>(), "job 7: render");
  // And the rate limit counts from that write.
  std::filesystem::remove(path_);
  now_ += 995ms;
  alive_.Mark("job 7: render");
  EXPECT_FALSE(std::filesystem::exists(path_));
}

TEST_F(AliveFileTest, ACleanExitRemovesTheFileItWrote) {
  {
    AliveFile alive(dir_ / "exiting.alive", [this] { return now_; });
    alive.Mark("waiting for work");
    ASSERT_TRUE(std::filesystem::exists(dir_ / "exiting.alive"));
  }
  EXPECT_FALSE(std::filesystem::exists(dir_ / "exiting.alive"));
  // One that never marked leaves alone what is there (another worker's file, say).
  WriteFileAtomic(dir_ / "other.alive", "{}\n");
  { AliveFile unmarked(dir_ / "other.alive", [this] { return now_; }); }
  EXPECT_TRUE(std::filesystem::exists(dir_ / "other.alive"));
}

TEST_F(AliveFileTest, AnUnwritablePathDoesNotThrow) {
  // A regular file where the directory should be: fails for root too.
  WriteFileAtomic(dir_ / "not-a-directory", "");
  AliveFile unwritable(dir_ / "not-a-directory" / "worker.alive", [this] { return now_; });
  EXPECT_NO_THROW(unwritable.Mark("started"));
  now_ += 2s;
  EXPECT_NO_THROW(unwritable.Mark("waiting for work"));
  EXPECT_FALSE(std::filesystem::exists(dir_ / "not-a-directory" / "worker.alive"));
}

}  // namespace
}  // namespace loom::worker
