#pragma once
// The durable job queue (DESIGN.md "Server, worker, client"; issue #6).
//
// Every job lives in one database: SQLite's DATA/jobs.db in WAL mode, or PostgreSQL
// (sql_db.h); a committed change survives kill -9 of the server. The queue is the single authority on a
// job's state; the gRPC service, the workers' leases and WatchJob are views of it.
//
// States: QUEUED -> LEASED -> RUNNING -> SUCCEEDED | FAILED | CANCELLED.
// - Lease gives the highest-priority job (FIFO within a priority) whose dependencies
//   all SUCCEEDED. A worker that failed a job is not given it again while another
//   live worker (seen within the lease duration: leasing, heartbeating, reporting or
//   just registered) that has not failed it exists; when there is none, the job goes
//   back to a worker that failed it, so a farm of one still uses every attempt,
//   unless that worker failed it blocklist_after times: then never (the job waits
//   for another worker, or a Retry, which clears its blocklist). Each lease
//   carries a fencing token, unique and increasing across the queue's lifetime:
//   Heartbeat, Complete, Fail and CheckLease must present the current one, so a
//   worker whose lease expired (or was voided by a server restart) can never report
//   on the job again, and a job never completes twice.
// - A lease ends by Complete, Fail, HandBack, expiry (no heartbeat before the deadline),
//   being stuck (heartbeats, but progress has not moved for `stuck_after_ms`), or a
//   server restart on SQLite (every LEASED/RUNNING job is requeued when the queue is
//   opened; on PostgreSQL leases outlive a server, as other servers may serve them).
//   Every way but Complete and HandBack is a failed attempt: the job is requeued while
//   attempts < max_attempts, otherwise it ends FAILED with the last error. A
//   failure the worker knows to be permanent (bad input) ends the job FAILED at once.
// - A job that ends FAILED or CANCELLED fails every job that depends on it
//   (transitively), with an error naming the dependency.
// - Cancel: a QUEUED job is CANCELLED at once. A leased one gets cancel_requested;
//   the worker learns it from its next Heartbeat (kCancelRequested) and then calls
//   Fail (any message), which ends the job CANCELLED instead of requeuing it. A
//   Complete after a cancel request also ends it CANCELLED (results dropped), and a
//   lease that expires with a cancel request pending ends CANCELLED too.
//
// The queue writes its own log lines on every transition ("leased by worker w1
// (attempt 1 of 3)", "lease expired: ...") into the job's log, next to the
// worker's lines from AppendLog.
//
// Thread-safe: one connection behind one mutex. One process per SQLite data
// directory. Any number of queues (servers) on one PostgreSQL: their writes take
// turns, so each job is leased once, and each hears of the others' commits
// (SqlDb::Listen), so a waiter on one wakes for a change made through another.

#include <array>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <numeric>
#include <optional>
#include <string>
#include <vector>

#include "loom/v1/job.pb.h"
#include "server/store/clock.h"

namespace loom::server {

class SqlDb;
class SqlListener;

struct JobQueueOptions {
  // A lease lasts this long after Lease and after each Heartbeat.
  int64_t lease_duration_ms = 30'000;
  // A leased job whose progress (fraction or stage) has not changed for this long
  // is treated like an expired lease.
  int64_t stuck_after_ms = 10 * 60'000;
  // Used when a submitted job leaves max_attempts at 0.
  uint32_t default_max_attempts = 3;
  // A worker that failed a job this many times (Fail, or a lease that expired or
  // stuck) is never given it again: the job's blocklist (>= 1).
  uint32_t blocklist_after = 3;
  // A job's log keeps its first and its last this many bytes (at least 4096); the
  // lines between are dropped, and Log shows a "… truncated …" line in their
  // place. A chatty or looping worker cannot fill the disk. One line is cut at
  // 4096 bytes.
  int64_t log_keep_bytes = 64 << 10;
};

struct JobLease {
  v1::Job job;         // state LEASED, attempts already counting this lease
  uint64_t token = 0;  // fencing token: present it on every call about this job
  int64_t deadline_ms = 0;
};

enum class HeartbeatStatus {
  kOk,               // lease extended; keep working
  kCancelRequested,  // lease extended; stop, then Fail() to end the job CANCELLED
  kStaleToken,       // the lease is gone (expired, requeued, finished): drop the job
};

// How a worker's failure of a job counts.
enum class Failure {
  kRetryable,  // a failed attempt: retried while attempts remain
  kPermanent,  // bad input (the spec does not validate, a mesh does not parse): FAILED now
};

struct JobFilter {
  std::vector<v1::JobState> states;  // empty: any state
  std::vector<v1::JobKind> kinds;    // empty: any kind
};

struct JobPage {
  std::vector<v1::Job> jobs;    // newest first (submission order, reversed)
  std::string next_page_token;  // empty on the last page
};

struct QueueDepth {
  // Jobs by [state][kind], indexed by JobState and JobKind.
  std::array<std::array<int64_t, v1::JobKind_ARRAYSIZE>, v1::JobState_ARRAYSIZE> by_state_kind{};
  // QUEUED with every dependency SUCCEEDED (leasable now), by kind.
  std::array<int64_t, v1::JobKind_ARRAYSIZE> ready_by_kind{};

  int64_t Count(v1::JobState state) const {
    return std::accumulate(by_state_kind[state].begin(), by_state_kind[state].end(), int64_t{0});
  }
  int64_t Ready() const { return std::accumulate(ready_by_kind.begin(), ready_by_kind.end(), int64_t{0}); }
};

// What this queue did since it was opened, counted by this process only (for
// metrics: several processes' counters add up).
struct QueueCounters {
  int64_t leases = 0;           // leases given
  int64_t lease_expiries = 0;   // leases ended because no heartbeat came before the deadline
  int64_t stuck_leases = 0;     // leases ended because progress stopped moving
  int64_t failed_attempts = 0;  // attempts that failed: a worker's Fail, an expiry, stuck, a restart
  int64_t retries = 0;          // failed attempts whose job was queued again for another

  QueueCounters& operator+=(const QueueCounters& other);
};

class JobQueue {
 public:
  // Opens (creating if needed) DATA/jobs.db and requeues every LEASED/RUNNING job
  // left by a previous process (a failed attempt: "server restarted ...").
  // `clock` must outlive the queue.
  JobQueue(const std::filesystem::path& data_dir, const Clock& clock, JobQueueOptions options = {});
  // The same tables in another database (server/store/sql_db.h): PostgreSQL's
  // (pg_db.h) is shared by every server on it.
  JobQueue(std::unique_ptr<SqlDb> db, const Clock& clock, JobQueueOptions options = {});
  ~JobQueue();
  JobQueue(const JobQueue&) = delete;
  JobQueue& operator=(const JobQueue&) = delete;

  const JobQueueOptions& options() const { return options_; }

  // --- Submitting ---------------------------------------------------------------

  // Adds a job. Read from `job`: kind and the matching payload (required),
  // priority, max_attempts (0: the default; at most 100), client_request_id,
  // depends_on (existing job ids), fabric_key, fabric_keys; every other field is the queue's.
  // A client_request_id already used returns that job unchanged (idempotent retry);
  // reusing one for a different kind or payload is kInvalidArgument.
  // Unknown dependency: kNotFound. A dependency already FAILED/CANCELLED: the job is
  // stored and returned FAILED at once, naming it.
  v1::Job Submit(const v1::Job& job);

  // A job with nothing left to do (a precompute whose fabric is already cached):
  // checked and stored as Submit does (client_request_id included), but SUCCEEDED
  // at once with `result_artifacts` (64-hex hashes) and `note` in its log; it is
  // never leased.
  v1::Job SubmitDone(const v1::Job& job, const std::vector<std::string>& result_artifacts, const std::string& note);

  // The precompute job that will produce fabric `fabric_key`: an active one
  // (QUEUED, LEASED or RUNNING) for that key is joined, otherwise one is created;
  // atomic, so concurrent callers get one job. A joined QUEUED job's priority is
  // raised to `priority` if lower (a render must not wait behind its own fabric).
  // SUCCEEDED jobs are not joined: the caller asks only after a cache miss, and a
  // finished precompute whose fabric was since evicted (or found corrupt) must run
  // again.
  v1::Job SubmitPrecomputeOnce(const v1::PrecomputeJob& precompute, const std::string& fabric_key,
                               int32_t priority);

  // --- Workers ------------------------------------------------------------------

  // Leases the next job for `worker_id` (non-empty), or nullopt if none is leasable.
  std::optional<JobLease> Lease(const std::string& worker_id);
  // Lease, waiting until a job becomes leasable (submit, requeue, a dependency
  // succeeding), `deadline` passes or Shutdown() is called. For LeaseJob's long poll.
  std::optional<JobLease> LeaseWait(const std::string& worker_id,
                                    std::chrono::steady_clock::time_point deadline);

  // Records progress (fraction in [0, 1], else kInvalidArgument) and extends the
  // lease; LEASED becomes RUNNING. Unknown id: kNotFound.
  HeartbeatStatus Heartbeat(const std::string& id, uint64_t token, double fraction,
                            const std::string& stage);

  // Throws kFailedPrecondition unless `token` is the job's current lease (kNotFound
  // for an unknown id). For uploads: an artifact is accepted only from the holder.
  void CheckLease(const std::string& id, uint64_t token) const;

  // Ends the lease successfully with the job's result artifact hashes (64 lowercase
  // hex digits each, else kInvalidArgument) and the worker's own time in the work
  // (timings.run_ms; >= 0, else kInvalidArgument); its progress reads 1, "done".
  // Returns the job as it ended:
  // SUCCEEDED, or CANCELLED if a cancel was requested meanwhile. Stale token:
  // kFailedPrecondition, nothing changes.
  v1::Job Complete(const std::string& id, uint64_t token, const std::vector<std::string>& result_artifacts,
                   double run_ms = 0);

  // Ends the lease as a failed attempt. The worker is not given this job again
  // while another live worker could take it (see above). Returns the job as it
  // ended: QUEUED (retried), FAILED (attempts used up, or a permanent failure), or
  // CANCELLED (a cancel was requested). Stale token: kFailedPrecondition.
  v1::Job Fail(const std::string& id, uint64_t token, const std::string& error,
               Failure failure = Failure::kRetryable);

  // Ends the lease without it counting as an attempt: a worker that is stopping
  // (SIGTERM) gives the job back unfinished through no fault of the job's. The job
  // is QUEUED again with the attempt given back (CANCELLED if a cancel was
  // requested), and any worker may take it, this one too. `reason` goes to the
  // log. `wait_for`, if not empty, names a job that the requeued one then depends
  // on too (a render whose fabric left the cache waits for its new precompute).
  // Stale token: kFailedPrecondition; unknown `wait_for`: kNotFound.
  v1::Job HandBack(const std::string& id, uint64_t token, const std::string& reason,
                   const std::string& wait_for = "");

  // Marks `worker_id` live now (RegisterWorker); leasing, heartbeats and reports
  // do it too.
  void WorkerSeen(const std::string& worker_id);

  // Ends every lease past its deadline or stuck, as failed attempts. Call it from a
  // timer (every second or so). Returns how many leases it ended.
  int RequeueExpired();

  // --- Clients ------------------------------------------------------------------

  // QUEUED: CANCELLED now. LEASED/RUNNING: cancel requested (see above).
  // Already finished: kFailedPrecondition. Unknown: kNotFound. Returns the job.
  v1::Job Cancel(const std::string& id);

  // A job not yet finished gets `priority` (a leased one keeps running); finished:
  // kFailedPrecondition. Returns the job.
  v1::Job SetPriority(const std::string& id, int32_t priority);

  // FAILED or CANCELLED jobs QUEUED again, all or none (anything else:
  // kFailedPrecondition naming it): attempts, error, progress, results and the
  // blocklist reset. Every FAILED or CANCELLED job they depend on, transitively, is
  // retried with them. Returns the jobs of `ids`, then those dependencies.
  std::vector<v1::Job> Retry(const std::vector<std::string>& ids);

  // Deletes finished jobs, all or none, with their logs; a job that an unfinished
  // job depends on is kFailedPrecondition. Returns the jobs as they were (their
  // results are the caller's to release).
  std::vector<v1::Job> Delete(const std::vector<std::string>& ids);

  // Unknown id: kNotFound.
  v1::Job Get(const std::string& id) const;

  // page_size <= 0: 100; at most 1000. page_token: "" or a previous next_page_token
  // (anything else: kInvalidArgument). Jobs submitted meanwhile never shift pages.
  // `max_bytes` > 0 ends a page early, before its jobs' serialized size would pass
  // it (a page holds at least one job).
  JobPage List(const JobFilter& filter, int page_size, const std::string& page_token,
               uint64_t max_bytes = 0) const;

  QueueDepth Depth() const;
  QueueCounters Counters() const;

  // A job's log: lines appended by its workers and by the queue, numbered from 0,
  // capped as log_keep_bytes says. Log returns the lines numbered from `from_line`
  // on, with a "… N lines truncated …" line for each run of dropped ones, and sets
  // `*next_line` (if given) to the number to ask from next time.
  void AppendLog(const std::string& id, const std::string& line);
  std::vector<std::string> Log(const std::string& id, int64_t from_line, int64_t* next_line = nullptr) const;

  // --- Watching -----------------------------------------------------------------

  // A counter that increases with every change to any job (state, progress, log):
  // on SQLite this process's, on PostgreSQL one sequence for every server on the store.
  uint64_t Version() const;

  // Waits until job `id` (any job if `id` is empty) has changed after `seen_version`
  // was read from Version(). Returns the new Version(), or nullopt at `deadline` or
  // Shutdown(). WatchJob: v = Version(); send Get(id) and Log(id, n); repeat with
  // WaitForChange(id, v, deadline).
  std::optional<uint64_t> WaitForChange(const std::string& id, uint64_t seen_version,
                                        std::chrono::steady_clock::time_point deadline) const;

  // --- Endings -------------------------------------------------------------------

  // `listener` is called once for every job that reaches SUCCEEDED, FAILED or
  // CANCELLED, however it gets there (a worker's report, a cancel, an expired
  // lease's last attempt, a failed dependency), after the change is committed and
  // without the queue's lock held: what the server holds for a job (its meshes'
  // pins) is released there. Set it once, before the queue is used by others;
  // jobs ended before (a restart's requeue ending a last attempt, when the queue
  // was opened) are told to it at once.
  void OnJobEnded(std::function<void(const std::string& id, v1::JobKind kind)> listener);

  // Wakes every waiter (LeaseWait, WaitForChange) and makes later waits return at
  // once, so that server shutdown is not held up by long polls.
  void Shutdown();

 private:
  struct Row;
  class Txn;

  // With mu_ held (and, for changes, inside a Txn).
  std::optional<Row> FindRow(const std::string& id) const;
  Row RequireRow(const std::string& id) const;
  Row RequireLease(const std::string& id, uint64_t token) const;
  v1::Job ToJob(const Row& row) const;
  v1::Job InsertJob(const v1::Job& job, int64_t now_ms);
  // Submit's checks of `job`, outside the lock.
  static void CheckSubmission(const v1::Job& job);
  // The job already stored under `job`'s client_request_id (kInvalidArgument if it
  // is a different job), nullopt when there is none.
  std::optional<v1::Job> FindRetry(const v1::Job& job) const;
  std::optional<JobLease> LeaseLocked(const std::string& worker_id);
  void NoteWorkerLocked(const std::string& worker_id, int64_t now_ms);
  void EndAttempt(const Row& row, const std::string& error, int64_t now_ms);
  // Counts a failure of `row`'s job against the worker holding its lease.
  void NoteWorkerFailureLocked(const Row& row);
  // Retry's reset of one job and, first, of its failed dependencies; appends the
  // dependencies it retried to `retried`.
  void RetryLocked(const Row& row, std::vector<int64_t>& retried);
  void Finish(const Row& row, v1::JobState state, const std::string& error, int64_t now_ms);
  // Ends every unfinished job depending on `dependency_seq` FAILED with `error`, transitively.
  void FailDependants(int64_t dependency_seq, const std::string& error, int64_t now_ms);
  void WriteLog(int64_t seq, const std::string& line);
  // SQL for the byte length of job_log's text column, in the database's dialect.
  std::string TextBytes() const;
  void Touch(int64_t seq);  // gives the job the next version
  // The last version stored; the next one (raising version_ to it).
  uint64_t StoredVersion() const;
  uint64_t NextVersion();
  // Another server's commit reached `payload` ("": unknown, read the store).
  void HeardOfChange(const std::string& payload);

  const Clock& clock_;
  const JobQueueOptions options_;
  mutable std::mutex mu_;
  mutable std::condition_variable changed_;
  std::unique_ptr<SqlDb> db_;
  std::function<void(const std::string&, v1::JobKind)> on_ended_;
  // Jobs ended by the open Txn, for on_ended_ once it commits.
  std::vector<std::pair<std::string, v1::JobKind>> ended_;
  // Jobs ended while no listener was set, for the listener once it is.
  std::vector<std::pair<std::string, v1::JobKind>> unheard_;
  uint64_t version_ = 0;
  bool shutdown_ = false;
  // Counted by the open Txn, added to counters_ once it commits.
  QueueCounters pending_, counters_;
  // Last: stopped before anything it touches is destroyed. Null on SQLite.
  std::unique_ptr<SqlListener> listener_;
};

}  // namespace loom::server
