#include "server/store/store_migration.h"

#include <google/protobuf/util/message_differencer.h>
#include <gtest/gtest.h>

#include <map>

#include "core/util/sha256.h"
#include "server/store/artifact_store.h"
#include "server/store/fabric_cache.h"
#include "server/store/job_queue.h"
#include "server/store/pg_db.h"
#include "store_test_util.h"
#include "tests/server/store/postgres_server.h"

namespace loom::server {
namespace {

namespace fs = std::filesystem;

v1::Job Render(const std::string& scene, std::vector<std::string> depends_on = {}, std::string request_id = "") {
  v1::Job job;
  job.set_kind(v1::JOB_KIND_RENDER);
  job.mutable_render()->mutable_scene()->set_name(scene);
  for (auto& id : depends_on) job.add_depends_on(id);
  job.set_client_request_id(request_id);
  return job;
}

int64_t CountRows(const std::string& conninfo, const std::string& table) {
  PgDb db(conninfo);
  auto count = db.Query("SELECT COUNT(*) FROM " + table);
  count.Step();
  return count.Int(0);
}

// A SQLite store holding a bit of everything, as a stopped server left it.
struct OldStore {
  std::vector<v1::Job> jobs;
  std::map<std::string, std::vector<std::string>> logs;
  std::vector<FabricEntry> fabrics;
  uint64_t artifact_bytes = 0;
  std::string running;  // a job leased when the server stopped
  uint64_t running_token = 0;
  uint64_t last_token = 0;
};

OldStore MakeOldStore(const fs::path& dir, FakeClock& clock) {
  ArtifactStore artifacts(dir);
  FabricCache cache(artifacts, clock);
  JobQueue queue(dir, clock);
  OldStore old;
  const std::string frame = artifacts.Put("a frame");
  const std::string manifest = artifacts.Put("{\"manifest\":1}");
  cache.Put(std::string(64, 'f'), {{"manifest.json", manifest}, {"lut.exr", artifacts.Put("a lut")}},
            "{\"manifest\":1}");
  cache.Pin(std::string(64, 'f'));
  artifacts.Pin(frame, "result:job-1");

  const std::string done = queue.Submit(Render("done")).id();
  const auto first = queue.Lease("w1");
  queue.AppendLog(done, "rendered in ünïcode");
  queue.Complete(done, first->token, {frame}, 12.5);
  queue.Submit(Render("waits", {done}, "request-7"));
  queue.Submit(Render("no request id"));
  v1::Job retried = Render("blocklisted");
  retried.set_max_attempts(5);
  retried.set_priority(10);  // leased first
  const std::string blocked = queue.Submit(retried).id();
  for (int i = 0; i < 3; ++i) {  // w1 fails it until it is blocklisted
    const auto lease = queue.Lease("w1");
    EXPECT_EQ(lease->job.id(), blocked);
    queue.Fail(blocked, lease->token, "w1 cannot");
  }
  const std::string cancelled = queue.Submit(Render("cancelled")).id();
  queue.Cancel(cancelled);
  const auto lease = queue.Lease("w2");
  queue.Heartbeat(lease->job.id(), lease->token, 0.5, "render");
  old.running = lease->job.id();
  old.running_token = old.last_token = lease->token;

  old.jobs = queue.List({}, 1000, "").jobs;
  for (const v1::Job& job : old.jobs) old.logs[job.id()] = queue.Log(job.id(), 0);
  old.fabrics = cache.List();
  old.artifact_bytes = artifacts.TotalBytes();
  return old;
}

TEST(StoreMigration, EverythingMovesAndGoesOnFromWhereItWas) {
  const fs::path dir = FreshDataDir();
  FakeClock clock;
  const OldStore old = MakeOldStore(dir, clock);
  ASSERT_EQ(old.jobs.size(), 5u);
  const std::string conninfo = FreshPostgresDatabase();

  const MigratedRows rows = MigrateSqliteStore(dir, conninfo);
  ASSERT_EQ(rows.front().first, "jobs");
  EXPECT_EQ(rows.front().second, 5);
  EXPECT_EQ(CountRows(conninfo, "job_log"), [&] {
    size_t lines = 0;
    for (const auto& [id, log] : old.logs) lines += log.size();
    return static_cast<int64_t>(lines);
  }());

  ArtifactStore artifacts(dir, std::make_unique<PgDb>(conninfo));
  FabricCache cache(artifacts, clock);
  JobQueue queue(std::make_unique<PgDb>(conninfo), clock);
  const std::vector<v1::Job> jobs = queue.List({}, 1000, "").jobs;
  ASSERT_EQ(jobs.size(), old.jobs.size());
  for (size_t i = 0; i < jobs.size(); ++i) {
    EXPECT_TRUE(google::protobuf::util::MessageDifferencer::Equals(jobs[i], old.jobs[i]))
        << jobs[i].DebugString() << "\nwas\n"
        << old.jobs[i].DebugString();
    EXPECT_EQ(queue.Log(jobs[i].id(), 0), old.logs.at(jobs[i].id())) << jobs[i].id();
  }
  // The lease held when the old server stopped lives on; ids and tokens go on.
  EXPECT_EQ(queue.Heartbeat(old.running, old.running_token, 0.75, "render"), HeartbeatStatus::kOk);
  EXPECT_EQ(queue.Submit(Render("new")).id(), "job-6");
  const auto next = queue.Lease("w3");
  ASSERT_TRUE(next.has_value());
  EXPECT_GT(next->token, old.last_token);
  EXPECT_LOOM_ERROR(queue.Submit(Render("other", {}, "request-7")), ErrorCode::kInvalidArgument, "request-7");

  const std::vector<FabricEntry> fabrics = cache.List();
  ASSERT_EQ(fabrics.size(), 1u);
  EXPECT_EQ(fabrics[0].key, old.fabrics[0].key);
  EXPECT_EQ(fabrics[0].manifest_json, old.fabrics[0].manifest_json);
  EXPECT_TRUE(fabrics[0].pinned);
  EXPECT_EQ(fabrics[0].total_bytes, old.fabrics[0].total_bytes);
  EXPECT_EQ(artifacts.TotalBytes(), old.artifact_bytes);
  EXPECT_LOOM_ERROR(artifacts.Remove(Sha256Hex("a frame")), ErrorCode::kFailedPrecondition, "result:job-1");
  EXPECT_EQ(artifacts.Read(Sha256Hex("a frame")), "a frame");

  // Once is all: the store is no longer empty, and nothing changes.
  EXPECT_LOOM_ERROR(MigrateSqliteStore(dir, conninfo), ErrorCode::kFailedPrecondition, "already holds 6 jobs rows");
  EXPECT_EQ(CountRows(conninfo, "jobs"), 6);
}

TEST(StoreMigration, NoSqliteStoreOrOneStillServedIsRefusedAndNothingIsCopied) {
  const std::string conninfo = FreshPostgresDatabase();
  const fs::path empty = FreshDataDir();
  EXPECT_LOOM_ERROR(MigrateSqliteStore(empty, conninfo), ErrorCode::kNotFound, "--data: no SQLite store to migrate");
  EXPECT_FALSE(fs::exists(empty / "jobs.db"));

  const fs::path dir = empty / "served";
  FakeClock clock;
  { ArtifactStore artifacts(dir); }
  JobQueue served(dir, clock);  // a server still runs on it
  served.Submit(Render("queued"));
  EXPECT_LOOM_ERROR(MigrateSqliteStore(dir, conninfo), ErrorCode::kFailedPrecondition, "in use by another process");
  EXPECT_EQ(CountRows(conninfo, "jobs"), 0);
}

}  // namespace
}  // namespace loom::server
