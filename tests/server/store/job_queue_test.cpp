#include "server/store/job_queue.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <cmath>
#include <latch>
#include <map>
#include <set>
#include <thread>

#include "server/store/pg_db.h"
#include "server/store/sqlite_db.h"
#include "tests/server/store/postgres_server.h"
#include "store_test_util.h"

namespace loom::server {
namespace {

using std::chrono::steady_clock;

const std::string kFabricKey(64, 'a');
// "w<n>", spelt out: GCC 12's -Wrestrict misfires on "w" + std::to_string(n).
std::string Worker(int n) {
  std::string name = "w";
  name += std::to_string(n);
  return name;
}

const std::string kHash = "2cf24dba5fb0a30e26e83b2ac5b9e29e1b161e5c1fa7425e73043362938b9824";

v1::Job Render(int32_t priority = 0, std::vector<std::string> depends_on = {}, std::string request_id = "") {
  v1::Job job;
  job.set_kind(v1::JOB_KIND_RENDER);
  job.set_priority(priority);
  job.mutable_render()->mutable_scene()->set_name("scene");
  for (auto& id : depends_on) job.add_depends_on(id);
  job.set_client_request_id(request_id);
  return job;
}

v1::PrecomputeJob PrecomputePayload() {
  v1::PrecomputeJob payload;
  payload.mutable_fabric()->mutable_knit();
  return payload;
}

JobFilter Kinds(std::vector<v1::JobKind> kinds) {
  JobFilter filter;
  filter.kinds = std::move(kinds);
  return filter;
}

JobFilter States(std::vector<v1::JobState> states) {
  JobFilter filter;
  filter.states = std::move(states);
  return filter;
}

// Every test on both databases: SQLite in a data directory, and a database of its
// own on a real PostgreSQL (postgres_server.h).
class JobQueueTest : public ::testing::TestWithParam<SqlDialect> {
 protected:
  JobQueueTest() : dir_(FreshDataDir()) {
    if (GetParam() == SqlDialect::kPostgres) conninfo_ = FreshPostgresDatabase();
    Reopen();
  }

  bool OnPostgres() const { return GetParam() == SqlDialect::kPostgres; }

  // Another queue on the same store, as a restarted server opens it.
  std::unique_ptr<JobQueue> Open(JobQueueOptions options = {}) {
    if (OnPostgres()) return std::make_unique<JobQueue>(std::make_unique<PgDb>(conninfo_), clock_, options);
    return std::make_unique<JobQueue>(dir_, clock_, options);
  }

  void Reopen(JobQueueOptions options = {}) {
    queue_.reset();
    options.lease_duration_ms = 30'000;
    options.stuck_after_ms = 300'000;
    queue_ = Open(options);
  }

  JobLease MustLease(const std::string& worker) {
    auto lease = queue_->Lease(worker);
    if (!lease) throw std::runtime_error("no job leasable for " + worker);
    return *lease;
  }

  int64_t CountJobs() { return queue_->List({}, 1000, "").jobs.size(); }

  std::filesystem::path dir_;
  std::string conninfo_;  // on PostgreSQL
  FakeClock clock_;
  std::unique_ptr<JobQueue> queue_;
};

INSTANTIATE_TEST_SUITE_P(Stores, JobQueueTest, kBothStores, StoreName);

TEST_P(JobQueueTest, HigherPriorityFirstThenFifo) {
  const auto a = queue_->Submit(Render(0)).id();
  const auto b = queue_->Submit(Render(5)).id();
  const auto c = queue_->Submit(Render(0)).id();
  const auto d = queue_->Submit(Render(5)).id();
  std::vector<std::string> order;
  while (auto lease = queue_->Lease("w1")) order.push_back(lease->job.id());
  EXPECT_EQ(order, (std::vector<std::string>{b, d, a, c}));
}

TEST_P(JobQueueTest, LeaseSetsStateAttemptsWorkerAndIncreasingTokens) {
  const auto submitted = queue_->Submit(Render());
  EXPECT_EQ(submitted.state(), v1::JOB_STATE_QUEUED);
  EXPECT_EQ(submitted.max_attempts(), 3u);
  EXPECT_EQ(submitted.timings().submitted_ms(), clock_.NowMs());
  queue_->Submit(Render());
  const JobLease first = MustLease("w1");
  const JobLease second = MustLease("w2");
  EXPECT_EQ(first.job.state(), v1::JOB_STATE_LEASED);
  EXPECT_EQ(first.job.attempts(), 1u);
  EXPECT_EQ(first.job.worker_id(), "w1");
  EXPECT_EQ(first.deadline_ms, clock_.NowMs() + 30'000);
  EXPECT_GT(second.token, first.token);
  EXPECT_FALSE(queue_->Lease("w3").has_value());
}

TEST_P(JobQueueTest, ClientRequestIdMakesSubmitIdempotent) {
  const auto first = queue_->Submit(Render(0, {}, "req-1"));
  const auto again = queue_->Submit(Render(0, {}, "req-1"));
  EXPECT_EQ(again.id(), first.id());
  EXPECT_EQ(again.client_request_id(), "req-1");
  auto different = Render(0, {}, "req-1");
  different.mutable_render()->mutable_scene()->set_name("other scene");
  EXPECT_LOOM_ERROR(queue_->Submit(different), ErrorCode::kInvalidArgument, "req-1");
  EXPECT_NE(queue_->Submit(Render(0, {}, "req-2")).id(), first.id());
  EXPECT_EQ(CountJobs(), 2);
}

TEST_P(JobQueueTest, ConcurrentPrecomputeOnceCreatesOneJob) {
  constexpr int kThreads = 20;
  std::latch start(kThreads);
  std::vector<std::string> ids(kThreads);
  std::vector<std::thread> threads;
  for (int i = 0; i < kThreads; ++i) {
    threads.emplace_back([&, i] {
      start.arrive_and_wait();
      ids[i] = queue_->SubmitPrecomputeOnce(PrecomputePayload(), kFabricKey, 0).id();
    });
  }
  for (auto& thread : threads) thread.join();
  EXPECT_EQ(std::set<std::string>(ids.begin(), ids.end()).size(), 1u);
  const auto page = queue_->List(Kinds({v1::JOB_KIND_PRECOMPUTE}), 100, "");
  ASSERT_EQ(page.jobs.size(), 1u);
  EXPECT_EQ(page.jobs[0].fabric_key(), kFabricKey);
  EXPECT_TRUE(page.jobs[0].has_precompute());
}

TEST_P(JobQueueTest, PrecomputeOnceJoinsActiveRaisesPriorityAndNeverJoinsFinished) {
  const auto first = queue_->SubmitPrecomputeOnce(PrecomputePayload(), kFabricKey, 1);
  const auto joined = queue_->SubmitPrecomputeOnce(PrecomputePayload(), kFabricKey, 7);
  EXPECT_EQ(joined.id(), first.id());
  EXPECT_EQ(joined.priority(), 7);
  EXPECT_EQ(queue_->SubmitPrecomputeOnce(PrecomputePayload(), kFabricKey, 2).priority(), 7);
  const auto other_key = queue_->SubmitPrecomputeOnce(PrecomputePayload(), std::string(64, 'b'), 0);
  EXPECT_NE(other_key.id(), first.id());

  const JobLease lease = MustLease("w1");
  ASSERT_EQ(lease.job.id(), first.id());
  EXPECT_EQ(queue_->SubmitPrecomputeOnce(PrecomputePayload(), kFabricKey, 0).id(), first.id());  // leased
  queue_->Complete(first.id(), lease.token, {kHash});
  // SUCCEEDED is not joined: the caller asks after a cache miss (evicted or corrupt fabric).
  const auto rerun = queue_->SubmitPrecomputeOnce(PrecomputePayload(), kFabricKey, 0);
  EXPECT_NE(rerun.id(), first.id());
  EXPECT_EQ(rerun.state(), v1::JOB_STATE_QUEUED);
  EXPECT_LOOM_ERROR(queue_->SubmitPrecomputeOnce(PrecomputePayload(), "not-a-key", 0),
                    ErrorCode::kInvalidArgument, "fabric_key");
}

TEST_P(JobQueueTest, RenderWaitsUntilEveryDependencySucceeded) {
  const auto p1 = queue_->SubmitPrecomputeOnce(PrecomputePayload(), kFabricKey, 0);
  const auto p2 = queue_->SubmitPrecomputeOnce(PrecomputePayload(), std::string(64, 'b'), 0);
  const auto render = queue_->Submit(Render(10, {p1.id(), p2.id()}));
  EXPECT_EQ(render.depends_on_size(), 2);
  EXPECT_EQ(queue_->Depth().Ready(), 2);

  const JobLease l1 = MustLease("w1");
  const JobLease l2 = MustLease("w1");
  EXPECT_EQ(l1.job.id(), p1.id());  // the render has the higher priority but is not ready
  EXPECT_EQ(l2.job.id(), p2.id());
  queue_->Complete(p1.id(), l1.token, {kHash});
  EXPECT_FALSE(queue_->Lease("w1").has_value());
  queue_->Complete(p2.id(), l2.token, {kHash});
  EXPECT_EQ(MustLease("w1").job.id(), render.id());
}

TEST_P(JobQueueTest, FailedOrCancelledDependencyFailsDependantsNamingIt) {
  auto precompute = queue_->SubmitPrecomputeOnce(PrecomputePayload(), kFabricKey, 0);
  const auto render = queue_->Submit(Render(0, {precompute.id()}));
  const auto second_level = queue_->Submit(Render(0, {render.id()}));
  for (const char* worker : {"w1", "w2", "w3"}) {
    const JobLease lease = MustLease(worker);
    queue_->Fail(precompute.id(), lease.token, "fit diverged");
  }
  EXPECT_EQ(queue_->Get(precompute.id()).state(), v1::JOB_STATE_FAILED);
  const auto failed = queue_->Get(render.id());
  EXPECT_EQ(failed.state(), v1::JOB_STATE_FAILED);
  EXPECT_NE(failed.error().find("dependency " + precompute.id() + " failed: fit diverged"), std::string::npos)
      << failed.error();
  EXPECT_EQ(queue_->Get(second_level.id()).state(), v1::JOB_STATE_FAILED);
  EXPECT_NE(queue_->Get(second_level.id()).error().find("dependency " + render.id()), std::string::npos);

  // Submitting against an already failed dependency fails at once.
  const auto late = queue_->Submit(Render(0, {precompute.id()}));
  EXPECT_EQ(late.state(), v1::JOB_STATE_FAILED);
  EXPECT_NE(late.error().find(precompute.id()), std::string::npos);

  // Cancellation cascades the same way.
  const auto other = queue_->SubmitPrecomputeOnce(PrecomputePayload(), std::string(64, 'c'), 0);
  const auto waiting = queue_->Submit(Render(0, {other.id()}));
  queue_->Cancel(other.id());
  EXPECT_EQ(queue_->Get(waiting.id()).state(), v1::JOB_STATE_FAILED);
  EXPECT_EQ(queue_->Get(waiting.id()).error(), "dependency " + other.id() + " was cancelled");
  EXPECT_FALSE(queue_->Lease("w9").has_value());
}

TEST_P(JobQueueTest, ExpiredLeaseIsRequeuedAndItsTokenRefused) {
  const auto id = queue_->Submit(Render()).id();
  const JobLease lease = MustLease("w1");
  clock_.Advance(20'000);
  EXPECT_EQ(queue_->Heartbeat(id, lease.token, 0.5, "fit"), HeartbeatStatus::kOk);  // deadline now +30 s
  clock_.Advance(29'999);
  EXPECT_EQ(queue_->RequeueExpired(), 0);
  clock_.Advance(1);
  EXPECT_EQ(queue_->RequeueExpired(), 1);
  const auto requeued = queue_->Get(id);
  EXPECT_EQ(requeued.state(), v1::JOB_STATE_QUEUED);
  EXPECT_EQ(requeued.worker_id(), "");
  EXPECT_NE(requeued.error().find("lease expired: worker w1"), std::string::npos) << requeued.error();

  EXPECT_EQ(queue_->Heartbeat(id, lease.token, 0.6, "fit"), HeartbeatStatus::kStaleToken);
  EXPECT_LOOM_ERROR(queue_->Complete(id, lease.token, {kHash}), ErrorCode::kFailedPrecondition, "stale");
  EXPECT_LOOM_ERROR(queue_->Fail(id, lease.token, "late"), ErrorCode::kFailedPrecondition, "stale");
  EXPECT_LOOM_ERROR(queue_->CheckLease(id, lease.token), ErrorCode::kFailedPrecondition, "stale");

  const JobLease again = MustLease("w2");
  EXPECT_EQ(again.job.attempts(), 2u);
  EXPECT_GT(again.token, lease.token);
  EXPECT_LOOM_ERROR(queue_->Complete(id, lease.token, {kHash}), ErrorCode::kFailedPrecondition, "newer lease");
  EXPECT_EQ(queue_->Complete(id, again.token, {kHash}).state(), v1::JOB_STATE_SUCCEEDED);
  EXPECT_LOOM_ERROR(queue_->Complete(id, again.token, {kHash}), ErrorCode::kFailedPrecondition, "SUCCEEDED");
}

TEST_P(JobQueueTest, HeartbeatRecordsProgressAndWrongTokenIsStale) {
  const auto id = queue_->Submit(Render()).id();
  const JobLease lease = MustLease("w1");
  EXPECT_EQ(queue_->Heartbeat(id, lease.token + 1, 0.1, "x"), HeartbeatStatus::kStaleToken);
  queue_->CheckLease(id, lease.token);
  EXPECT_LOOM_ERROR(queue_->CheckLease(id, lease.token + 1), ErrorCode::kFailedPrecondition, "stale");
  EXPECT_EQ(queue_->Heartbeat(id, lease.token, 0.25, "acquisition: view 16/64"), HeartbeatStatus::kOk);
  const auto running = queue_->Get(id);
  EXPECT_EQ(running.state(), v1::JOB_STATE_RUNNING);
  EXPECT_DOUBLE_EQ(running.progress().fraction(), 0.25);
  EXPECT_EQ(running.progress().stage(), "acquisition: view 16/64");
  EXPECT_LOOM_ERROR(queue_->Heartbeat(id, lease.token, 1.5, "x"), ErrorCode::kInvalidArgument, "[0, 1]");
  EXPECT_LOOM_ERROR(queue_->Heartbeat(id, lease.token, std::nan(""), "x"), ErrorCode::kInvalidArgument, "[0, 1]");
  EXPECT_LOOM_ERROR(queue_->Complete(id, lease.token, {kHash}, -1), ErrorCode::kInvalidArgument, "run_ms");
  const auto done = queue_->Complete(id, lease.token, {kHash}, 12.5);
  EXPECT_EQ(done.state(), v1::JOB_STATE_SUCCEEDED);
  EXPECT_EQ(done.result_artifacts_size(), 1);
  EXPECT_EQ(done.result_artifacts(0), kHash);
  EXPECT_EQ(done.timings().finished_ms(), clock_.NowMs());
  EXPECT_DOUBLE_EQ(done.timings().run_ms(), 12.5);
}

TEST_P(JobQueueTest, ADatabaseFromBeforeRunTimesGainsTheColumnWhenOpened) {
  if (OnPostgres()) GTEST_SKIP() << "SQLite data directories from before run times only";
  const auto id = queue_->Submit(Render()).id();
  queue_.reset();
  SqliteDb(dir_ / "jobs.db").Exec("ALTER TABLE jobs DROP COLUMN run_ms");
  Reopen();
  const JobLease lease = MustLease("w1");
  ASSERT_EQ(lease.job.id(), id);
  EXPECT_DOUBLE_EQ(queue_->Complete(id, lease.token, {kHash}, 7).timings().run_ms(), 7);
}

TEST_P(JobQueueTest, AttemptsAreBoundedThenFailedWithTheLastError) {
  const auto id = queue_->Submit(Render()).id();
  for (int attempt = 1; attempt <= 3; ++attempt) {
    const JobLease lease = MustLease(Worker(attempt));
    const auto after = queue_->Fail(id, lease.token, "error " + std::to_string(attempt));
    EXPECT_EQ(after.state(), attempt < 3 ? v1::JOB_STATE_QUEUED : v1::JOB_STATE_FAILED);
    EXPECT_EQ(after.attempts(), static_cast<uint32_t>(attempt));
  }
  const auto failed = queue_->Get(id);
  EXPECT_EQ(failed.error(), "error 3 (worker w3)");
  EXPECT_FALSE(queue_->Lease("w4").has_value());
}

TEST_P(JobQueueTest, ExpiryCountsAsAnAttempt) {
  auto job = Render();
  job.set_max_attempts(1);
  const auto id = queue_->Submit(job).id();
  MustLease("w1");
  clock_.Advance(30'000);
  EXPECT_EQ(queue_->RequeueExpired(), 1);
  EXPECT_EQ(queue_->Get(id).state(), v1::JOB_STATE_FAILED);
  EXPECT_NE(queue_->Get(id).error().find("lease expired"), std::string::npos);
}

TEST_P(JobQueueTest, WorkerThatFailedAJobIsNotGivenItAgainWhileAnotherLiveWorkerCouldTakeIt) {
  const auto id = queue_->Submit(Render()).id();
  queue_->WorkerSeen("w2");
  queue_->Fail(id, MustLease("w1").token, "out of GPU memory");
  EXPECT_FALSE(queue_->Lease("w1").has_value());
  const JobLease other = MustLease("w2");
  EXPECT_EQ(other.job.id(), id);
  EXPECT_EQ(other.job.error(), "out of GPU memory (worker w1)");
}

TEST_P(JobQueueTest, TheOnlyLiveWorkerGetsAJobItFailedBackUntilAttemptsRunOut) {
  const auto id = queue_->Submit(Render()).id();
  queue_->WorkerSeen("w2");
  queue_->Fail(id, MustLease("w1").token, "transient 1");
  EXPECT_FALSE(queue_->Lease("w1").has_value());  // w2 is live and has not failed it
  clock_.Advance(30'001);                          // w2 not seen for a lease duration: gone
  const JobLease second = MustLease("w1");
  EXPECT_EQ(second.job.attempts(), 2u);
  queue_->Fail(id, second.token, "transient 2");
  // A worker that failed it too does not keep it from w1.
  queue_->WorkerSeen("w2");
  queue_->Fail(id, MustLease("w2").token, "transient 3");
  const auto failed = queue_->Get(id);
  EXPECT_EQ(failed.state(), v1::JOB_STATE_FAILED);
  EXPECT_EQ(failed.error(), "transient 3 (worker w2)");
}

// The per-job blocklist (issue 22): a worker that failed a job blocklist_after
// times never gets it again, not even as the only worker; a retry clears it.
TEST_P(JobQueueTest, AWorkerIsBlocklistedFromAJobAfterItsFailuresUntilARetry) {
  JobQueueOptions options;
  options.blocklist_after = 2;
  Reopen(options);
  auto job = Render();
  job.set_max_attempts(10);
  const auto id = queue_->Submit(job).id();
  queue_->Fail(id, MustLease("w1").token, "driver crash");
  queue_->Fail(id, MustLease("w1").token, "driver crash");  // the only live worker: it may try again
  EXPECT_FALSE(queue_->Lease("w1").has_value());            // blocklisted now, alone or not
  const v1::Job waiting = queue_->Get(id);
  EXPECT_EQ(waiting.state(), v1::JOB_STATE_QUEUED);
  ASSERT_EQ(waiting.blocklisted_workers_size(), 1);
  EXPECT_EQ(waiting.blocklisted_workers(0), "w1");
  const std::vector<std::string> log = queue_->Log(id, 0);
  EXPECT_EQ(std::count_if(log.begin(), log.end(),
                          [](const std::string& line) { return line.find("w1 is blocklisted") != std::string::npos; }),
            1);
  // Another worker takes it; a lease that expires counts as its failure too.
  MustLease("w2");
  clock_.Advance(30'001);
  EXPECT_EQ(queue_->RequeueExpired(), 1);
  MustLease("w2");
  clock_.Advance(30'001);
  EXPECT_EQ(queue_->RequeueExpired(), 1);
  EXPECT_FALSE(queue_->Lease("w2").has_value());
  EXPECT_EQ(queue_->Get(id).blocklisted_workers_size(), 2);
  // A cancel and a retry: attempts and the blocklist start again.
  queue_->Cancel(id);
  const std::vector<v1::Job> retried = queue_->Retry({id});
  ASSERT_EQ(retried.size(), 1u);
  EXPECT_EQ(retried[0].state(), v1::JOB_STATE_QUEUED);
  EXPECT_EQ(retried[0].attempts(), 0u);
  EXPECT_EQ(retried[0].blocklisted_workers_size(), 0);
  EXPECT_EQ(MustLease("w1").job.id(), id);
}

TEST_P(JobQueueTest, RetryQueuesFailedJobsAndTheFailedJobsTheyDependOn) {
  auto failing = Render();
  failing.set_max_attempts(1);
  const auto precompute = queue_->SubmitPrecomputeOnce(PrecomputePayload(), kFabricKey, 0);
  const auto render = queue_->Submit(Render(0, {precompute.id()}));
  const auto other = queue_->Submit(failing);
  const auto queued = queue_->Submit(Render(-5));
  queue_->Fail(precompute.id(), MustLease("w1").token, "bad yarn", Failure::kPermanent);
  queue_->Fail(other.id(), MustLease("w1").token, "flaky");
  ASSERT_EQ(queue_->Get(render.id()).state(), v1::JOB_STATE_FAILED);
  // All or none: a queued job among them refuses the lot.
  EXPECT_LOOM_ERROR(queue_->Retry({other.id(), queued.id()}), ErrorCode::kFailedPrecondition,
                    queued.id() + " is QUEUED");
  EXPECT_EQ(queue_->Get(other.id()).state(), v1::JOB_STATE_FAILED);

  const std::vector<v1::Job> retried = queue_->Retry({render.id(), other.id()});
  ASSERT_EQ(retried.size(), 3u);
  EXPECT_EQ(retried[0].id(), render.id());
  EXPECT_EQ(retried[1].id(), other.id());
  EXPECT_EQ(retried[2].id(), precompute.id());  // the dependency, retried with its render
  for (const v1::Job& job : retried) {
    EXPECT_EQ(job.state(), v1::JOB_STATE_QUEUED) << job.id();
    EXPECT_EQ(job.attempts(), 0u) << job.id();
    EXPECT_EQ(job.error(), "") << job.id();
    EXPECT_EQ(job.timings().finished_ms(), 0) << job.id();
  }
  // The render waits for its precompute again, and runs after it.
  EXPECT_EQ(MustLease("w1").job.id(), precompute.id());
  EXPECT_LOOM_ERROR(queue_->Retry({"job-999"}), ErrorCode::kNotFound, "job-999");
}

TEST_P(JobQueueTest, SetPriorityReordersWaitingJobsAndRefusesFinishedOnes) {
  const auto first = queue_->Submit(Render(0)).id();
  const auto second = queue_->Submit(Render(0)).id();
  EXPECT_EQ(queue_->SetPriority(second, 9).priority(), 9);
  EXPECT_EQ(MustLease("w1").job.id(), second);
  const JobLease lease = MustLease("w1");
  EXPECT_EQ(lease.job.id(), first);
  EXPECT_EQ(queue_->SetPriority(first, 3).state(), v1::JOB_STATE_LEASED);  // keeps running
  queue_->Complete(first, lease.token, {});
  EXPECT_LOOM_ERROR(queue_->SetPriority(first, 1), ErrorCode::kFailedPrecondition, "already SUCCEEDED");
}

TEST_P(JobQueueTest, DeleteRemovesFinishedJobsAndRefusesOneAnUnfinishedJobWaitsFor) {
  v1::Job precompute_job;
  precompute_job.set_kind(v1::JOB_KIND_PRECOMPUTE);
  *precompute_job.mutable_precompute() = PrecomputePayload();
  const auto done = queue_->SubmitDone(precompute_job, {kHash}, "cached");
  const auto render = queue_->Submit(Render(0, {done.id()}));
  const auto running = queue_->Submit(Render(0));
  EXPECT_LOOM_ERROR(queue_->Delete({done.id()}), ErrorCode::kFailedPrecondition,
                    "unfinished job " + render.id() + " depends on it");
  const JobLease lease = MustLease("w1");
  EXPECT_LOOM_ERROR(queue_->Delete({lease.job.id()}), ErrorCode::kFailedPrecondition, "only finished jobs");
  queue_->Cancel(render.id() == lease.job.id() ? running.id() : render.id());
  queue_->Complete(lease.job.id(), lease.token, {kHash});
  const std::vector<v1::Job> deleted = queue_->Delete({done.id(), render.id(), running.id(), done.id()});
  ASSERT_EQ(deleted.size(), 3u);
  EXPECT_EQ(deleted[0].result_artifacts(0), kHash);
  EXPECT_EQ(CountJobs(), 0);
  EXPECT_LOOM_ERROR(queue_->Get(done.id()), ErrorCode::kNotFound, done.id());
  // Tokens still only grow after their leases' rows are gone.
  queue_->Submit(Render());
  EXPECT_GT(MustLease("w1").token, lease.token);
}

TEST_P(JobQueueTest, AHandBackUsesUpNoAttempt) {
  auto job = Render();
  job.set_max_attempts(1);
  const auto id = queue_->Submit(job).id();
  queue_->WorkerSeen("w2");
  for (int stop = 0; stop < 3; ++stop) {
    const JobLease lease = MustLease("w1");  // the same worker: a hand-back excludes no one
    EXPECT_EQ(lease.job.attempts(), 1u);
    const auto requeued = queue_->HandBack(id, lease.token, "worker w1 is stopping");
    EXPECT_EQ(requeued.state(), v1::JOB_STATE_QUEUED);
    EXPECT_EQ(requeued.attempts(), 0u);
    EXPECT_LOOM_ERROR(queue_->HandBack(id, lease.token, "again"), ErrorCode::kFailedPrecondition, "stale");
  }
  const JobLease last = MustLease("w1");
  EXPECT_EQ(queue_->Complete(id, last.token, {kHash}).state(), v1::JOB_STATE_SUCCEEDED);
  const auto log = queue_->Log(id, 0);
  EXPECT_NE(std::find(log.begin(), log.end(),
                      "[queue] handed back by worker w1 (worker w1 is stopping); requeued, the attempt not counted"),
            log.end());
}

TEST_P(JobQueueTest, AHandBackCanMakeTheJobWaitForAnother) {
  const auto render = queue_->Submit(Render()).id();
  const JobLease lease = MustLease("w1");
  const auto precompute = queue_->SubmitPrecomputeOnce(PrecomputePayload(), kFabricKey, 0).id();
  const auto waiting = queue_->HandBack(render, lease.token, "fabric left the cache", precompute);
  EXPECT_EQ(waiting.state(), v1::JOB_STATE_QUEUED);
  EXPECT_EQ(waiting.attempts(), 0u);
  EXPECT_EQ(std::vector<std::string>(waiting.depends_on().begin(), waiting.depends_on().end()),
            std::vector<std::string>{precompute});
  const JobLease next = MustLease("w1");
  EXPECT_EQ(next.job.id(), precompute);  // the render waits for it
  EXPECT_FALSE(queue_->Lease("w2").has_value());
  queue_->Complete(precompute, next.token, {kHash});
  EXPECT_EQ(MustLease("w2").job.id(), render);
}

TEST_P(JobQueueTest, AHandBackAfterACancelRequestEndsCancelled) {
  const auto id = queue_->Submit(Render()).id();
  const JobLease lease = MustLease("w1");
  queue_->Cancel(id);
  EXPECT_EQ(queue_->HandBack(id, lease.token, "stopping").state(), v1::JOB_STATE_CANCELLED);
}

TEST_P(JobQueueTest, APermanentFailureEndsTheJobFailedAtOnce) {
  const auto id = queue_->Submit(Render()).id();
  const auto ended = queue_->Fail(id, MustLease("w1").token, "scene.render.width: 0 is below 1", Failure::kPermanent);
  EXPECT_EQ(ended.state(), v1::JOB_STATE_FAILED);
  EXPECT_EQ(ended.attempts(), 1u);
  EXPECT_EQ(ended.max_attempts(), 3u);
  EXPECT_EQ(ended.error(), "scene.render.width: 0 is below 1 (worker w1)");
  EXPECT_FALSE(queue_->Lease("w2").has_value());
}

TEST_P(JobQueueTest, JobWhoseProgressStopsMovingIsStuck) {
  const auto id = queue_->Submit(Render()).id();
  const JobLease lease = MustLease("w1");
  // Heartbeats keep the lease alive, but with the same progress for 300 s.
  for (int i = 0; i < 10; ++i) {
    EXPECT_EQ(queue_->Heartbeat(id, lease.token, 0.5, "fit level 0"), HeartbeatStatus::kOk);
    EXPECT_EQ(queue_->RequeueExpired(), 0);
    clock_.Advance(29'000);
  }
  EXPECT_EQ(queue_->Heartbeat(id, lease.token, 0.5, "fit level 0"), HeartbeatStatus::kOk);
  clock_.Advance(10'000);  // 300 s since the lease began, progress never moved
  EXPECT_EQ(queue_->RequeueExpired(), 1);
  const auto requeued = queue_->Get(id);
  EXPECT_EQ(requeued.state(), v1::JOB_STATE_QUEUED);
  EXPECT_NE(requeued.error().find("stuck: no progress for 300 s on worker w1"), std::string::npos)
      << requeued.error();
  EXPECT_EQ(queue_->Heartbeat(id, lease.token, 0.6, "fit level 1"), HeartbeatStatus::kStaleToken);
}

TEST_P(JobQueueTest, MovingProgressIsNotStuck) {
  const auto id = queue_->Submit(Render()).id();
  const JobLease lease = MustLease("w1");
  for (int i = 1; i <= 20; ++i) {
    clock_.Advance(29'000);
    EXPECT_EQ(queue_->Heartbeat(id, lease.token, i / 100.0, "fit"), HeartbeatStatus::kOk);
    EXPECT_EQ(queue_->RequeueExpired(), 0);
  }
  EXPECT_EQ(queue_->Get(id).state(), v1::JOB_STATE_RUNNING);
}

TEST_P(JobQueueTest, CancelQueuedJobEndsItAtOnce) {
  const auto id = queue_->Submit(Render()).id();
  const auto cancelled = queue_->Cancel(id);
  EXPECT_EQ(cancelled.state(), v1::JOB_STATE_CANCELLED);
  EXPECT_FALSE(queue_->Lease("w1").has_value());
  EXPECT_LOOM_ERROR(queue_->Cancel(id), ErrorCode::kFailedPrecondition, "already CANCELLED");
}

TEST_P(JobQueueTest, CancelRunningJobReachesWorkerAtNextHeartbeat) {
  const auto id = queue_->Submit(Render()).id();
  const JobLease lease = MustLease("w1");
  EXPECT_EQ(queue_->Heartbeat(id, lease.token, 0.1, "render"), HeartbeatStatus::kOk);
  const auto requested = queue_->Cancel(id);
  EXPECT_EQ(requested.state(), v1::JOB_STATE_RUNNING);
  EXPECT_TRUE(requested.cancel_requested());
  EXPECT_EQ(queue_->Heartbeat(id, lease.token, 0.2, "render"), HeartbeatStatus::kCancelRequested);
  const auto ended = queue_->Fail(id, lease.token, "stopped: cancel requested");
  EXPECT_EQ(ended.state(), v1::JOB_STATE_CANCELLED);
  EXPECT_EQ(ended.attempts(), 1u);
  EXPECT_LOOM_ERROR(queue_->Cancel(id), ErrorCode::kFailedPrecondition, "already CANCELLED");
}

TEST_P(JobQueueTest, CompleteAfterCancelRequestEndsCancelled) {
  const auto id = queue_->Submit(Render()).id();
  const JobLease lease = MustLease("w1");
  queue_->Cancel(id);
  const auto ended = queue_->Complete(id, lease.token, {kHash});
  EXPECT_EQ(ended.state(), v1::JOB_STATE_CANCELLED);
  EXPECT_EQ(ended.result_artifacts_size(), 0);
  EXPECT_LOOM_ERROR(queue_->Complete(id, lease.token, {kHash}), ErrorCode::kFailedPrecondition, "stale");
}

TEST_P(JobQueueTest, ExpiredLeaseWithCancelRequestEndsCancelled) {
  const auto id = queue_->Submit(Render()).id();
  MustLease("w1");
  queue_->Cancel(id);
  clock_.Advance(30'000);
  EXPECT_EQ(queue_->RequeueExpired(), 1);
  EXPECT_EQ(queue_->Get(id).state(), v1::JOB_STATE_CANCELLED);
}

TEST_P(JobQueueTest, ReopenKeepsEveryJobAndOnSqliteRequeuesLeasedOnes) {
  const auto queued = queue_->Submit(Render(1)).id();
  const auto running = queue_->Submit(Render(5)).id();
  const auto done = queue_->Submit(Render(3)).id();
  const JobLease lease = MustLease("w1");
  ASSERT_EQ(lease.job.id(), running);
  queue_->Heartbeat(running, lease.token, 0.4, "render");
  const JobLease done_lease = MustLease("w1");
  queue_->Complete(done, done_lease.token, {kHash});
  queue_->AppendLog(queued, "a worker line");

  Reopen();  // the server restarts
  EXPECT_EQ(CountJobs(), 3);
  EXPECT_EQ(queue_->Get(queued).state(), v1::JOB_STATE_QUEUED);
  EXPECT_EQ(queue_->Get(done).state(), v1::JOB_STATE_SUCCEEDED);
  EXPECT_EQ(queue_->Get(done).result_artifacts(0), kHash);
  EXPECT_EQ(queue_->Log(queued, 0).back(), "a worker line");
  if (OnPostgres()) {
    // Its worker may report through another server: the lease outlives this one.
    EXPECT_EQ(queue_->Get(running).state(), v1::JOB_STATE_RUNNING);
    EXPECT_EQ(queue_->Heartbeat(running, lease.token, 0.5, "render"), HeartbeatStatus::kOk);
    EXPECT_EQ(queue_->Complete(running, lease.token, {kHash}).attempts(), 1u);
    EXPECT_GT(MustLease("w1").token, done_lease.token);
    return;
  }
  const auto requeued = queue_->Get(running);
  EXPECT_EQ(requeued.state(), v1::JOB_STATE_QUEUED);
  EXPECT_EQ(requeued.attempts(), 1u);
  EXPECT_NE(requeued.error().find("server restarted"), std::string::npos);

  EXPECT_EQ(queue_->Heartbeat(running, lease.token, 0.5, "render"), HeartbeatStatus::kStaleToken);
  EXPECT_LOOM_ERROR(queue_->Complete(running, lease.token, {kHash}), ErrorCode::kFailedPrecondition, "stale");
  const JobLease fresh = MustLease("w1");
  EXPECT_EQ(fresh.job.id(), running);
  EXPECT_GT(fresh.token, done_lease.token);  // tokens keep growing across restarts
}

TEST_P(JobQueueTest, SurvivesKillDashNineOfTheServer) {
  queue_.reset();  // the child process opens the queue itself
  // The child submits three jobs, leases one (token 1) and finishes another, then
  // dies by SIGKILL: no destructor, no checkpoint, nothing flushed on the way out.
  EXPECT_EXIT(
      {
        const std::unique_ptr<JobQueue> server = Open();
        for (int priority : {3, 2, 1}) server->Submit(Render(priority));
        const auto done = server->Lease("w1");
        server->Complete(done->job.id(), done->token, {kHash});
        const auto running = server->Lease("w1");
        server->Heartbeat(running->job.id(), running->token, 0.5, "render");
        server->AppendLog(running->job.id(), "half way");
        std::raise(SIGKILL);
      },
      ::testing::KilledBySignal(SIGKILL), "");
  Reopen();  // the restarted server; the dead one's database lock went with it
  EXPECT_EQ(CountJobs(), 3);
  EXPECT_EQ(queue_->Get("job-1").state(), v1::JOB_STATE_SUCCEEDED);
  EXPECT_EQ(queue_->Log("job-2", 0)[2], "half way");
  EXPECT_EQ(queue_->Get("job-3").state(), v1::JOB_STATE_QUEUED);
  if (OnPostgres()) {  // the lease lives on, for its worker to report through any server
    EXPECT_EQ(queue_->Get("job-2").state(), v1::JOB_STATE_RUNNING);
    EXPECT_EQ(queue_->Heartbeat("job-2", 2, 0.6, "render"), HeartbeatStatus::kOk);
    return;
  }
  const auto requeued = queue_->Get("job-2");
  EXPECT_EQ(requeued.state(), v1::JOB_STATE_QUEUED);
  EXPECT_NE(requeued.error().find("server restarted"), std::string::npos);
  EXPECT_EQ(queue_->Heartbeat("job-2", 2, 0.6, "render"), HeartbeatStatus::kStaleToken);
  const JobLease again = MustLease("w1");
  EXPECT_EQ(again.job.id(), "job-2");
  EXPECT_EQ(again.token, 3u);
}

TEST_P(JobQueueTest, SecondQueueOnTheSameDataDirectoryIsRefused) {
  if (OnPostgres()) GTEST_SKIP() << "several servers on one PostgreSQL are the point";
  EXPECT_LOOM_ERROR(JobQueue(dir_, clock_), ErrorCode::kFailedPrecondition, "in use by another process");
  queue_->Submit(Render());  // the first one is unaffected
  EXPECT_EQ(CountJobs(), 1);
}

TEST_P(JobQueueTest, FourWorkersCompleteTwoHundredJobsEachExactlyOnce) {
  constexpr int kJobs = 200;
  for (int i = 0; i < kJobs; ++i) queue_->Submit(Render(i % 3));
  std::mutex mu;
  std::map<std::string, int> completions;
  std::vector<std::thread> workers;
  for (int w = 0; w < 4; ++w) {
    workers.emplace_back([&, w] {
      const std::string worker = Worker(w);
      while (auto lease = queue_->Lease(worker)) {
        queue_->Heartbeat(lease->job.id(), lease->token, 0.5, "render");
        queue_->Complete(lease->job.id(), lease->token, {kHash});
        std::lock_guard lock(mu);
        ++completions[lease->job.id()];
      }
    });
  }
  for (auto& worker : workers) worker.join();
  EXPECT_EQ(completions.size(), static_cast<size_t>(kJobs));
  for (const auto& [id, count] : completions) EXPECT_EQ(count, 1) << id;
  const QueueDepth depth = queue_->Depth();
  EXPECT_EQ(depth.Count(v1::JOB_STATE_SUCCEEDED), kJobs);
  EXPECT_EQ(depth.Count(v1::JOB_STATE_QUEUED), 0);
  for (const auto& job : queue_->List({}, 1000, "").jobs) EXPECT_EQ(job.attempts(), 1u) << job.id();
}

// Several servers on one PostgreSQL: each its own queue on its own connection. Every
// job is leased and completed exactly once, whichever server a worker asks.
TEST_P(JobQueueTest, ThreeServersOnOneStoreCompleteEachJobExactlyOnce) {
  if (!OnPostgres()) GTEST_SKIP() << "one server per SQLite data directory";
  constexpr int kJobs = 300;
  for (int i = 0; i < kJobs; ++i) queue_->Submit(Render(i % 3));
  std::vector<std::unique_ptr<JobQueue>> servers;
  for (int s = 0; s < 3; ++s) servers.push_back(Open());
  std::mutex mu;
  std::map<std::string, int> completions;
  std::vector<std::string> errors;
  std::vector<std::thread> workers;
  for (int w = 0; w < 6; ++w) {
    workers.emplace_back([&, w] {
      JobQueue& server = *servers[w % 3];
      const std::string worker = Worker(w);
      while (auto lease = server.Lease(worker)) {
        try {
          server.Heartbeat(lease->job.id(), lease->token, 0.5, "render");
          server.Complete(lease->job.id(), lease->token, {kHash});
        } catch (const Error& error) {  // a job leased twice: the first lease went stale
          std::lock_guard lock(mu);
          errors.push_back(error.what());
          continue;
        }
        std::lock_guard lock(mu);
        ++completions[lease->job.id()];
      }
    });
  }
  for (auto& worker : workers) worker.join();
  EXPECT_TRUE(errors.empty()) << errors.size() << " reports refused, the first: " << errors.front();
  EXPECT_EQ(completions.size(), static_cast<size_t>(kJobs));
  for (const auto& [id, count] : completions) EXPECT_EQ(count, 1) << id;
  EXPECT_EQ(queue_->Depth().Count(v1::JOB_STATE_SUCCEEDED), kJobs);
  for (const auto& job : queue_->List({}, 1000, "").jobs) EXPECT_EQ(job.attempts(), 1u) << job.id();
}

TEST_P(JobQueueTest, LeaseWaitWakesOnSubmitAndOnShutdown) {
  EXPECT_FALSE(queue_->LeaseWait("w1", steady_clock::now()).has_value());  // deadline passed: no wait

  std::optional<JobLease> got;
  std::thread waiter([&] { got = queue_->LeaseWait("w1", steady_clock::now() + std::chrono::minutes(5)); });
  const auto id = queue_->Submit(Render()).id();
  waiter.join();  // returns because of the submit, not the deadline
  ASSERT_TRUE(got.has_value());
  EXPECT_EQ(got->job.id(), id);

  std::optional<JobLease> none = JobLease{};
  std::thread idle([&] { none = queue_->LeaseWait("w1", steady_clock::now() + std::chrono::minutes(5)); });
  queue_->Shutdown();
  idle.join();
  EXPECT_FALSE(none.has_value());
}

TEST_P(JobQueueTest, WaitForChangeSeesChangesToTheWatchedJob) {
  const auto a = queue_->Submit(Render()).id();
  const auto b = queue_->Submit(Render()).id();
  const uint64_t seen = queue_->Version();
  const auto past = steady_clock::now();
  EXPECT_FALSE(queue_->WaitForChange(a, seen, past).has_value());
  queue_->AppendLog(b, "b moved");
  EXPECT_FALSE(queue_->WaitForChange(a, seen, past).has_value());  // another job changed
  EXPECT_EQ(queue_->WaitForChange("", seen, past), queue_->Version());

  std::optional<uint64_t> woke;
  std::thread watcher([&] { woke = queue_->WaitForChange(a, seen, steady_clock::now() + std::chrono::minutes(5)); });
  queue_->AppendLog(a, "a moved");
  watcher.join();
  ASSERT_TRUE(woke.has_value());
  EXPECT_GT(*woke, seen);
  EXPECT_LOOM_ERROR(queue_->WaitForChange("job-999", 0, past), ErrorCode::kNotFound, "job-999");
}

// Servers on one PostgreSQL hear of each other's commits: a worker waiting on one
// gets a job submitted through another, and a watcher on one sees a change made
// through another, though its own server has made many more changes meanwhile.
TEST_P(JobQueueTest, WaitersOnOneServerWakeForChangesThroughAnother) {
  if (!OnPostgres()) GTEST_SKIP() << "one server per SQLite data directory";
  const std::unique_ptr<JobQueue> other = Open();
  const auto bound = [] { return steady_clock::now() + std::chrono::minutes(1); };
  std::optional<JobLease> got;
  std::thread waiter([&] { got = other->LeaseWait("w1", bound()); });
  const auto id = queue_->Submit(Render()).id();
  waiter.join();
  ASSERT_TRUE(got.has_value()) << "no wake-up within a minute";
  EXPECT_EQ(got->job.id(), id);

  const auto watched = queue_->Submit(Render()).id();
  const auto busy = other->Submit(Render()).id();
  for (int i = 0; i < 20; ++i) other->AppendLog(busy, "line " + std::to_string(i));
  const uint64_t seen = other->Version();
  std::optional<uint64_t> woke, any;
  std::thread watcher([&] { woke = other->WaitForChange(watched, seen, bound()); });
  std::thread any_watcher([&] { any = other->WaitForChange("", seen, bound()); });
  queue_->AppendLog(watched, "moved through the first server");
  watcher.join();
  any_watcher.join();
  ASSERT_TRUE(woke.has_value()) << "no wake-up within a minute";
  ASSERT_TRUE(any.has_value()) << "no wake-up within a minute";
  EXPECT_GT(*woke, seen);
  EXPECT_GT(*any, seen);
  EXPECT_EQ(other->Log(watched, 0).back(), "moved through the first server");
}

TEST_P(JobQueueTest, ListPagesNewestFirstWithFilters) {
  std::vector<std::string> ids;
  for (int i = 0; i < 5; ++i) {
    ids.push_back(i % 2 ? queue_->SubmitPrecomputeOnce(PrecomputePayload(), std::string(64, 'a' + i), 0).id()
                        : queue_->Submit(Render()).id());
  }
  const auto first = queue_->List({}, 2, "");
  ASSERT_EQ(first.jobs.size(), 2u);
  EXPECT_EQ(first.jobs[0].id(), ids[4]);
  EXPECT_EQ(first.jobs[1].id(), ids[3]);
  queue_->Submit(Render());  // a new job does not shift later pages
  const auto second = queue_->List({}, 2, first.next_page_token);
  ASSERT_EQ(second.jobs.size(), 2u);
  EXPECT_EQ(second.jobs[0].id(), ids[2]);
  const auto third = queue_->List({}, 2, second.next_page_token);
  ASSERT_EQ(third.jobs.size(), 1u);
  EXPECT_EQ(third.jobs[0].id(), ids[0]);
  EXPECT_EQ(third.next_page_token, "");

  const auto precomputes = queue_->List(Kinds({v1::JOB_KIND_PRECOMPUTE}), 0, "");
  ASSERT_EQ(precomputes.jobs.size(), 2u);
  EXPECT_EQ(precomputes.jobs[0].id(), ids[3]);
  queue_->Cancel(ids[0]);
  const auto cancelled = queue_->List(States({v1::JOB_STATE_CANCELLED, v1::JOB_STATE_FAILED}), 0, "");
  ASSERT_EQ(cancelled.jobs.size(), 1u);
  EXPECT_EQ(cancelled.jobs[0].id(), ids[0]);
  EXPECT_LOOM_ERROR(queue_->List({}, 2, "bogus"), ErrorCode::kInvalidArgument, "bogus");
}

// A page ends before its jobs pass max_bytes (ListJobs: a default client's 4 MiB
// receive limit), and still holds one job that is larger on its own.
TEST_P(JobQueueTest, ListPagesEndBeforeTheirBytesPassTheCap) {
  constexpr uint64_t kCap = 100'000;
  for (int i = 0; i < 10; ++i) {
    v1::Job job = Render();
    // Not the scene's name: a job carries that twice (Job.name).
    job.mutable_render()->mutable_scene()->add_objects()->set_name(std::string(30'000, 'a' + i));
    queue_->Submit(job);
  }
  v1::Job huge = Render();
  huge.mutable_render()->mutable_scene()->add_objects()->set_name(std::string(3 * kCap, 'z'));
  queue_->Submit(huge);
  std::vector<size_t> sizes;
  std::string token;
  int jobs = 0;
  do {
    const JobPage page = queue_->List({}, 1000, token, kCap);
    uint64_t bytes = 0;
    for (const v1::Job& job : page.jobs) bytes += job.ByteSizeLong();
    if (page.jobs.size() > 1) {
      EXPECT_LE(bytes, kCap);
    }
    sizes.push_back(page.jobs.size());
    jobs += static_cast<int>(page.jobs.size());
    token = page.next_page_token;
  } while (!token.empty());
  EXPECT_EQ(jobs, 11);
  EXPECT_EQ(sizes, (std::vector<size_t>{1, 3, 3, 3, 1}));  // the huge one alone, newest first
}

TEST_P(JobQueueTest, LogKeepsWorkerAndQueueLinesInOrder) {
  const auto id = queue_->Submit(Render()).id();
  const JobLease lease = MustLease("w1");
  queue_->AppendLog(id, "loading scene");
  queue_->AppendLog(id, "rendering");
  queue_->Complete(id, lease.token, {kHash});
  const auto log = queue_->Log(id, 0);
  ASSERT_EQ(log.size(), 5u);
  EXPECT_EQ(log[0], "[queue] submitted");
  EXPECT_EQ(log[1], "[queue] leased by worker w1 (attempt 1 of 3)");
  EXPECT_EQ(log[2], "loading scene");
  EXPECT_EQ(log[3], "rendering");
  EXPECT_EQ(log[4], "[queue] SUCCEEDED");
  EXPECT_EQ(queue_->Log(id, 3), (std::vector<std::string>{"rendering", "[queue] SUCCEEDED"}));
  EXPECT_TRUE(queue_->Log(id, 5).empty());
  EXPECT_LOOM_ERROR(queue_->Log(id, -1), ErrorCode::kInvalidArgument, "negative");
}

TEST_P(JobQueueTest, ALogKeepsItsFirstAndLastBytesWithATruncatedLineBetween) {
  Reopen(JobQueueOptions{.log_keep_bytes = 4096});
  const auto id = queue_->Submit(Render()).id();
  const auto numbered = [](int n) {
    char text[24];
    std::snprintf(text, sizeof text, "line %03d ", n);
    return std::string(text) + std::string(51, 'x');  // 60 bytes
  };
  for (int n = 0; n < 300; ++n) queue_->AppendLog(id, numbered(n));  // 18000 bytes

  int64_t next = 0;
  const auto log = queue_->Log(id, 0, &next);
  size_t bytes = 0;
  for (const auto& line : log) bytes += line.size();
  EXPECT_LE(bytes, 2 * 4096 + 200u);
  EXPECT_GE(bytes, 2 * 4096 - 2 * 60u);
  EXPECT_EQ(log.front(), "[queue] submitted");
  EXPECT_EQ(log[1], numbered(0));
  EXPECT_EQ(log.back(), numbered(299));
  const auto marker = std::find_if(log.begin(), log.end(), [](const std::string& l) { return l.find("truncated") != std::string::npos; });
  ASSERT_NE(marker, log.end());
  EXPECT_EQ(std::count_if(log.begin(), log.end(), [](const std::string& l) { return l.find("truncated") != std::string::npos; }), 1);
  EXPECT_EQ(*(marker - 1), numbered(static_cast<int>(marker - log.begin()) - 2));  // the head is whole up to the cut
  EXPECT_EQ(next, 301);  // "[queue] submitted" and 300 lines

  // A reader resuming inside the dropped lines is told so, then gets the tail.
  const auto resumed = queue_->Log(id, 100);
  EXPECT_NE(resumed.front().find("truncated"), std::string::npos) << resumed.front();
  EXPECT_EQ(resumed.back(), numbered(299));

  // One oversized line is cut.
  queue_->AppendLog(id, std::string(10'000, 'y'));
  const auto last = queue_->Log(id, next).back();
  EXPECT_EQ(last.substr(0, 4096), std::string(4096, 'y'));
  EXPECT_NE(last.find("5904 bytes cut"), std::string::npos);
  // …never inside a character: "é" is two bytes, the cut falls between them.
  queue_->AppendLog(id, std::string(4095, 'z') + "é" + std::string(10, 'z'));
  const auto whole = queue_->Log(id, next + 1).back();
  EXPECT_EQ(whole.substr(0, 4096), std::string(4095, 'z') + " ");
  EXPECT_NE(whole.find("12 bytes cut"), std::string::npos) << whole.substr(4000);
  EXPECT_LOOM_ERROR(Reopen(JobQueueOptions{.log_keep_bytes = 100}), ErrorCode::kInvalidArgument, "log_keep_bytes");
}

TEST_P(JobQueueTest, DepthCountsStatesAndReadyJobs) {
  const auto precompute = queue_->SubmitPrecomputeOnce(PrecomputePayload(), kFabricKey, 0);
  queue_->Submit(Render(0, {precompute.id()}));
  queue_->Submit(Render());
  const auto cancelled = queue_->Submit(Render());
  queue_->Cancel(cancelled.id());
  MustLease("w1");
  const QueueDepth depth = queue_->Depth();
  EXPECT_EQ(depth.Count(v1::JOB_STATE_QUEUED), 2);
  EXPECT_EQ(depth.Count(v1::JOB_STATE_LEASED), 1);
  EXPECT_EQ(depth.Count(v1::JOB_STATE_CANCELLED), 1);
  EXPECT_EQ(depth.Ready(), 1);  // the render waiting on the precompute is not ready
  // The same by kind.
  EXPECT_EQ(depth.by_state_kind[v1::JOB_STATE_QUEUED][v1::JOB_KIND_RENDER], 2);
  EXPECT_EQ(depth.by_state_kind[v1::JOB_STATE_QUEUED][v1::JOB_KIND_PRECOMPUTE], 0);
  EXPECT_EQ(depth.by_state_kind[v1::JOB_STATE_LEASED][v1::JOB_KIND_PRECOMPUTE], 1);
  EXPECT_EQ(depth.by_state_kind[v1::JOB_STATE_CANCELLED][v1::JOB_KIND_RENDER], 1);
  EXPECT_EQ(depth.ready_by_kind[v1::JOB_KIND_RENDER], 1);
  EXPECT_EQ(depth.ready_by_kind[v1::JOB_KIND_PRECOMPUTE], 0);
}

TEST_P(JobQueueTest, CountersCountLeasesExpiriesFailuresAndRetries) {
  JobQueueOptions options;
  options.default_max_attempts = 2;
  Reopen(options);
  const auto a = queue_->Submit(Render()).id();
  const auto b = queue_->Submit(Render()).id();
  const JobLease first = MustLease("w1");   // a, attempt 1
  const JobLease second = MustLease("w2");  // b, attempt 1
  queue_->Fail(first.job.id(), first.token, "crashed");  // a requeued: a retry
  clock_.Advance(30'000);
  EXPECT_EQ(queue_->RequeueExpired(), 1);  // b's lease expired: requeued, a retry
  const JobLease third = MustLease("w3");
  const JobLease fourth = MustLease("w3");
  queue_->Fail(third.job.id(), third.token, "crashed again");  // its second attempt: FAILED, no retry
  queue_->Complete(fourth.job.id(), fourth.token, {kHash});
  // A stale report changes nothing, counters included.
  EXPECT_LOOM_ERROR(queue_->Fail(second.job.id(), second.token, "late"), ErrorCode::kFailedPrecondition, "stale");

  const QueueCounters counters = queue_->Counters();
  EXPECT_EQ(counters.leases, 4);
  EXPECT_EQ(counters.lease_expiries, 1);
  EXPECT_EQ(counters.stuck_leases, 0);
  EXPECT_EQ(counters.failed_attempts, 3);
  EXPECT_EQ(counters.retries, 2);
  EXPECT_EQ(queue_->Get(a).state(), v1::JOB_STATE_FAILED);
  EXPECT_EQ(queue_->Get(b).state(), v1::JOB_STATE_SUCCEEDED);

  // A job whose progress stops is a stuck lease, not an expiry.
  const auto c = queue_->Submit(Render()).id();
  const JobLease stuck = MustLease("w1");
  for (int i = 0; i < 11; ++i) {  // heartbeats keep the lease, progress stays put for 330 s
    clock_.Advance(30'000);
    if (queue_->Heartbeat(c, stuck.token, 0.1, "fit") == HeartbeatStatus::kStaleToken) break;
    queue_->RequeueExpired();
  }
  queue_->RequeueExpired();
  EXPECT_EQ(queue_->Counters().stuck_leases, 1);
  EXPECT_EQ(queue_->Counters().lease_expiries, 1);
}

TEST_P(JobQueueTest, BadInputIsRefusedAndNothingStoredChanges) {
  const auto id = queue_->Submit(Render()).id();
  const JobLease lease = MustLease("w1");
  EXPECT_LOOM_ERROR(queue_->Get("job-42"), ErrorCode::kNotFound, "job-42");
  EXPECT_LOOM_ERROR(queue_->Get(""), ErrorCode::kNotFound, "no job ''");
  EXPECT_LOOM_ERROR(queue_->Get("job-01"), ErrorCode::kNotFound, "job-01");
  EXPECT_LOOM_ERROR(queue_->Cancel("nope"), ErrorCode::kNotFound, "nope");
  EXPECT_LOOM_ERROR(queue_->Heartbeat("job-42", 1, 0, ""), ErrorCode::kNotFound, "job-42");
  EXPECT_LOOM_ERROR(queue_->AppendLog("job-42", "x"), ErrorCode::kNotFound, "job-42");
  EXPECT_LOOM_ERROR(queue_->Complete(id, lease.token, {""}), ErrorCode::kInvalidArgument, "result_artifacts[0]");
  EXPECT_LOOM_ERROR(queue_->Complete(id, lease.token, {kHash, "ABC"}), ErrorCode::kInvalidArgument,
                    "result_artifacts[1]");
  EXPECT_LOOM_ERROR(queue_->Lease(""), ErrorCode::kInvalidArgument, "worker_id");

  v1::Job no_payload;
  no_payload.set_kind(v1::JOB_KIND_RENDER);
  EXPECT_LOOM_ERROR(queue_->Submit(no_payload), ErrorCode::kInvalidArgument, "payload");
  EXPECT_LOOM_ERROR(queue_->Submit(v1::Job()), ErrorCode::kInvalidArgument, "JOB_KIND_UNSPECIFIED");
  auto too_many = Render();
  too_many.set_max_attempts(1000);
  EXPECT_LOOM_ERROR(queue_->Submit(too_many), ErrorCode::kInvalidArgument, "max_attempts");
  EXPECT_LOOM_ERROR(queue_->Submit(Render(0, {id, "job-77"}, "req")), ErrorCode::kNotFound, "job-77");

  EXPECT_EQ(CountJobs(), 1);
  queue_->CheckLease(id, lease.token);  // the lease survived the bad calls
  EXPECT_EQ(queue_->Complete(id, lease.token, {kHash}).state(), v1::JOB_STATE_SUCCEEDED);
  EXPECT_EQ(queue_->Submit(Render(0, {}, "req")).state(), v1::JOB_STATE_QUEUED);  // "req" was not taken
}

}  // namespace
}  // namespace loom::server
