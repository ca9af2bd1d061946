#include "server/store/job_queue.h"

#include <google/protobuf/io/coded_stream.h>
#include <google/protobuf/io/zero_copy_stream_impl_lite.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <utility>

#include "core/util/error.h"
#include "loom/v1/job_state.h"
#include "server/store/artifact_store.h"
#include "server/store/sqlite_db.h"

namespace loom::server {
namespace {

using v1::JobState;

constexpr uint32_t kMaxAttemptsCap = 100;
constexpr int kDefaultPageSize = 100;
constexpr int kMaxPageSize = 1000;
constexpr size_t kMaxLogLineBytes = 4096;

constexpr const char* kSchema = R"sql(
CREATE TABLE IF NOT EXISTS jobs (
  seq INTEGER PRIMARY KEY AUTOINCREMENT,  -- the job id is "job-<seq>"
  kind INTEGER NOT NULL,
  state INTEGER NOT NULL,
  priority INTEGER NOT NULL,
  attempts INTEGER NOT NULL DEFAULT 0,
  max_attempts INTEGER NOT NULL,
  payload BLOB NOT NULL,                  -- a Job holding only its payload oneof
  client_request_id TEXT UNIQUE,          -- NULL when not given
  fabric_key TEXT NOT NULL,
  progress_fraction REAL NOT NULL DEFAULT 0,
  progress_stage TEXT NOT NULL DEFAULT '',
  submitted_ms INTEGER NOT NULL,
  started_ms INTEGER NOT NULL DEFAULT 0,
  finished_ms INTEGER NOT NULL DEFAULT 0,
  results TEXT NOT NULL DEFAULT '',       -- artifact hashes, newline-separated
  error TEXT NOT NULL DEFAULT '',
  worker_id TEXT NOT NULL DEFAULT '',
  lease_token INTEGER NOT NULL DEFAULT 0, -- 0: not leased
  lease_deadline_ms INTEGER NOT NULL DEFAULT 0,
  progress_moved_ms INTEGER NOT NULL DEFAULT 0,
  cancel_requested INTEGER NOT NULL DEFAULT 0,
  version INTEGER NOT NULL DEFAULT 0,
  run_ms REAL NOT NULL DEFAULT 0);        -- the worker's own time in the work
CREATE INDEX IF NOT EXISTS jobs_by_readiness ON jobs(state, priority DESC, seq);
CREATE INDEX IF NOT EXISTS jobs_by_fabric ON jobs(fabric_key, state);
CREATE TABLE IF NOT EXISTS job_deps (
  job_seq INTEGER NOT NULL REFERENCES jobs(seq),
  dep_seq INTEGER NOT NULL REFERENCES jobs(seq));
CREATE INDEX IF NOT EXISTS job_deps_by_job ON job_deps(job_seq);
CREATE INDEX IF NOT EXISTS job_deps_by_dep ON job_deps(dep_seq);
CREATE TABLE IF NOT EXISTS job_failed_workers (
  job_seq INTEGER NOT NULL REFERENCES jobs(seq),
  worker_id TEXT NOT NULL,
  failures INTEGER NOT NULL DEFAULT 1,    -- blocklisted from the job at blocklist_after
  PRIMARY KEY (job_seq, worker_id));
CREATE TABLE IF NOT EXISTS job_log (
  job_seq INTEGER NOT NULL REFERENCES jobs(seq),
  line INTEGER NOT NULL,
  text TEXT NOT NULL,
  PRIMARY KEY (job_seq, line));
-- One row per lease ever granted: AUTOINCREMENT never reuses a token, so fencing
-- tokens only grow, across restarts too.
CREATE TABLE IF NOT EXISTS leases (
  token INTEGER PRIMARY KEY AUTOINCREMENT,
  job_seq INTEGER NOT NULL REFERENCES jobs(seq),
  worker_id TEXT NOT NULL,
  leased_ms INTEGER NOT NULL);
)sql";

constexpr const char* kRowColumns =
    "seq, kind, state, priority, attempts, max_attempts, payload, client_request_id, fabric_key, "
    "progress_fraction, progress_stage, submitted_ms, started_ms, finished_ms, results, error, worker_id, "
    "lease_token, lease_deadline_ms, progress_moved_ms, cancel_requested, run_ms, fabric_keys";

std::string JobId(int64_t seq) { return "job-" + std::to_string(seq); }

// "job-<seq>" -> seq; nullopt for anything else (then no such job exists).
std::optional<int64_t> ParseJobId(std::string_view id) {
  constexpr std::string_view kPrefix = "job-";
  if (!id.starts_with(kPrefix)) return std::nullopt;
  const std::string_view digits = id.substr(kPrefix.size());
  if (digits.empty() || digits.front() == '0') return std::nullopt;
  int64_t seq = 0;
  const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), seq);
  if (ec != std::errc() || end != digits.data() + digits.size()) return std::nullopt;
  return seq;
}

// "SUCCEEDED" rather than "JOB_STATE_SUCCEEDED" in messages.
std::string StateName(JobState state) { return v1::JobState_Name(state).substr(std::string_view("JOB_STATE_").size()); }

// The payload alone, serialised deterministically: stored, and compared when a
// client request id is reused.
std::string PayloadBytes(const v1::Job& job) {
  v1::Job payload;
  if (job.has_precompute()) *payload.mutable_precompute() = job.precompute();
  if (job.has_render()) *payload.mutable_render() = job.render();
  if (job.has_animate()) *payload.mutable_animate() = job.animate();
  std::string bytes;
  {
    google::protobuf::io::StringOutputStream stream(&bytes);
    google::protobuf::io::CodedOutputStream coded(&stream);
    coded.SetSerializationDeterministic(true);
    payload.SerializeToCodedStream(&coded);
  }
  return bytes;
}

// Lists stored in one column (result hashes, fabric keys), one per line.
template <typename Strings>
std::string JoinLines(const Strings& lines) {
  std::string joined;
  for (const std::string& line : lines) joined += (joined.empty() ? "" : "\n") + line;
  return joined;
}
std::vector<std::string> SplitLines(const std::string& joined) {
  std::vector<std::string> lines;
  for (size_t begin = 0; begin < joined.size();) {
    const size_t end = std::min(joined.find('\n', begin), joined.size());
    lines.push_back(joined.substr(begin, end - begin));
    begin = end + 1;
  }
  return lines;
}

// The error of a job whose dependency `id` ended in `state` (FAILED or CANCELLED).
std::string DependencyError(const std::string& id, JobState state, const std::string& error) {
  return "dependency " + id + (state == v1::JOB_STATE_FAILED ? " failed: " + error : " was cancelled");
}

std::string Seconds(int64_t ms) { return std::to_string(ms / 1000) + " s"; }

// Columns added after a table's first release: a data directory made by an older
// server gains them when opened (CREATE TABLE IF NOT EXISTS leaves it as it was).
void AddColumnIfMissing(SqlDb& db, const std::string& table, const std::string& column,
                        const std::string& definition) {
  auto found = db.Query("SELECT COUNT(*) FROM pragma_table_info(?) WHERE name = ?", table, column);
  found.Step();
  if (found.Int(0) == 0) db.Exec("ALTER TABLE " + table + " ADD COLUMN " + column + " " + definition);
}

}  // namespace

// The mutable columns of one job row, read in one query.
struct JobQueue::Row {
  int64_t seq = 0;
  v1::JobKind kind = v1::JOB_KIND_UNSPECIFIED;
  JobState state = v1::JOB_STATE_UNSPECIFIED;
  int32_t priority = 0;
  uint32_t attempts = 0;
  uint32_t max_attempts = 0;
  std::string payload;
  std::string client_request_id;
  std::string fabric_key;
  double progress_fraction = 0;
  std::string progress_stage;
  int64_t submitted_ms = 0, started_ms = 0, finished_ms = 0;
  std::string results;
  std::string error;
  std::string worker_id;
  uint64_t lease_token = 0;
  int64_t lease_deadline_ms = 0;
  int64_t progress_moved_ms = 0;
  bool cancel_requested = false;
  double run_ms = 0;
  std::string fabric_keys;  // a render's, one per line

  std::string id() const { return JobId(seq); }
  bool leased() const { return state == v1::JOB_STATE_LEASED || state == v1::JOB_STATE_RUNNING; }

  // Rows of `jobs` matching `where` (SQL after FROM jobs), bound to `args`.
  template <typename... Args>
  static std::vector<Row> Select(SqlDb& db, std::string_view where, const Args&... args) {
    std::vector<Row> rows;
    for (auto query = db.Query(std::string("SELECT ") + kRowColumns + " FROM jobs " + std::string(where), args...);
         query.Step();) {
      rows.push_back(Read(query));
    }
    return rows;
  }

  static Row Read(const SqlQuery& s) {
    Row row;
    row.seq = s.Int(0);
    row.kind = static_cast<v1::JobKind>(s.Int(1));
    row.state = static_cast<JobState>(s.Int(2));
    row.priority = static_cast<int32_t>(s.Int(3));
    row.attempts = static_cast<uint32_t>(s.Int(4));
    row.max_attempts = static_cast<uint32_t>(s.Int(5));
    row.payload = s.Text(6);
    row.client_request_id = s.Text(7);
    row.fabric_key = s.Text(8);
    row.progress_fraction = s.Double(9);
    row.progress_stage = s.Text(10);
    row.submitted_ms = s.Int(11);
    row.started_ms = s.Int(12);
    row.finished_ms = s.Int(13);
    row.results = s.Text(14);
    row.error = s.Text(15);
    row.worker_id = s.Text(16);
    row.lease_token = static_cast<uint64_t>(s.Int(17));
    row.lease_deadline_ms = s.Int(18);
    row.progress_moved_ms = s.Int(19);
    row.cancel_requested = s.Int(20) != 0;
    row.run_ms = s.Double(21);
    row.fabric_keys = s.Text(22);
    return row;
  }
};

// A change to the queue: holds the mutex and a write transaction; Commit() makes
// it durable, wakes every waiter, releases the mutex and then tells the ended-job
// listener about the jobs the change ended. Destroyed uncommitted (an exception),
// it rolls back and leaves the queue as it was.
class JobQueue::Txn {
 public:
  explicit Txn(JobQueue& queue) : queue_(queue), lock_(queue.mu_), txn_(*queue.db_) {
    queue_.ended_.clear();
    queue_.pending_ = {};
  }
  void Commit() {
    txn_.Commit();
    queue_.counters_ += std::exchange(queue_.pending_, {});
    queue_.changed_.notify_all();
    auto ended = std::exchange(queue_.ended_, {});
    const auto listener = queue_.on_ended_;
    if (!listener) queue_.unheard_.insert(queue_.unheard_.end(), ended.begin(), ended.end());
    lock_.unlock();
    if (listener) {
      for (const auto& [id, kind] : ended) listener(id, kind);
    }
  }

 private:
  JobQueue& queue_;
  std::unique_lock<std::mutex> lock_;
  SqlDb::Transaction txn_;
};

JobQueue::JobQueue(const std::filesystem::path& data_dir, const Clock& clock, JobQueueOptions options)
    : clock_(clock), options_(options), db_(std::make_unique<SqliteDb>(data_dir / "jobs.db")) {
  if (options_.default_max_attempts == 0 || options_.default_max_attempts > kMaxAttemptsCap ||
      options_.blocklist_after == 0 ||
      options_.lease_duration_ms <= 0 || options_.stuck_after_ms <= 0 ||
      options_.log_keep_bytes < static_cast<int64_t>(kMaxLogLineBytes)) {
    throw Error(ErrorCode::kInvalidArgument,
                "job queue options: lease and stuck times must be positive, default_max_attempts in [1, 100], "
                "blocklist_after at least 1, log_keep_bytes at least 4096");
  }
  db_->Exec(kSchema);
  // Live workers, in memory only (TEMP): a restarted server learns them again as
  // they register and lease.
  db_->Exec("CREATE TEMP TABLE live_workers (worker_id TEXT PRIMARY KEY, seen_ms INTEGER NOT NULL)");
  AddColumnIfMissing(*db_, "jobs", "run_ms", "REAL NOT NULL DEFAULT 0");
  AddColumnIfMissing(*db_, "job_failed_workers", "failures", "INTEGER NOT NULL DEFAULT 1");
  AddColumnIfMissing(*db_, "jobs", "fabric_keys", "TEXT NOT NULL DEFAULT ''");
  {
    auto max_version = db_->Query("SELECT COALESCE(MAX(version), 0) FROM jobs");
    max_version.Step();
    version_ = static_cast<uint64_t>(max_version.Int(0));
  }
  // Leases held before a restart are void: their workers talk to a new process.
  Txn txn(*this);
  const int64_t now = clock_.NowMs();
  for (const Row& row : Row::Select(*db_, "WHERE state IN (?, ?)", static_cast<int>(v1::JOB_STATE_LEASED),
                                    static_cast<int>(v1::JOB_STATE_RUNNING))) {
    EndAttempt(row, "server restarted while the job was leased by worker " + row.worker_id, now);
  }
  txn.Commit();
}

JobQueue::~JobQueue() = default;

// --- Row access -------------------------------------------------------------------

std::optional<JobQueue::Row> JobQueue::FindRow(const std::string& id) const {
  const auto seq = ParseJobId(id);
  if (!seq) return std::nullopt;
  auto rows = Row::Select(*db_, "WHERE seq = ?", *seq);
  if (rows.empty()) return std::nullopt;
  return std::move(rows.front());
}

JobQueue::Row JobQueue::RequireRow(const std::string& id) const {
  auto row = FindRow(id);
  if (!row) throw Error(ErrorCode::kNotFound, "no job '" + id + "'");
  return *row;
}

JobQueue::Row JobQueue::RequireLease(const std::string& id, uint64_t token) const {
  Row row = RequireRow(id);
  if (!row.leased() || row.lease_token != token) {
    throw Error(ErrorCode::kFailedPrecondition,
                "job " + id + ": lease token " + std::to_string(token) + " is stale (the job is " +
                    StateName(row.state) + (row.leased() ? " under a newer lease" : "") + ")");
  }
  return row;
}

v1::Job JobQueue::ToJob(const Row& row) const {
  v1::Job job;
  if (!job.ParseFromString(row.payload)) {
    throw Error(ErrorCode::kInternal, "job " + row.id() + ": stored payload does not parse");
  }
  job.set_id(row.id());
  job.set_name(job.has_precompute() ? job.precompute().fabric().name()
               : job.has_render()   ? job.render().scene().name()
                                    : job.animate().animation().name());
  job.set_kind(row.kind);
  job.set_state(row.state);
  job.set_priority(row.priority);
  job.set_attempts(row.attempts);
  job.set_max_attempts(row.max_attempts);
  job.mutable_progress()->set_fraction(row.progress_fraction);
  job.mutable_progress()->set_stage(row.progress_stage);
  job.mutable_timings()->set_submitted_ms(row.submitted_ms);
  job.mutable_timings()->set_started_ms(row.started_ms);
  job.mutable_timings()->set_finished_ms(row.finished_ms);
  job.mutable_timings()->set_run_ms(row.run_ms);
  for (std::string& hash : SplitLines(row.results)) job.add_result_artifacts(std::move(hash));
  job.set_error(row.error);
  job.set_client_request_id(row.client_request_id);
  for (auto deps = db_->Query("SELECT dep_seq FROM job_deps WHERE job_seq = ? ORDER BY rowid", row.seq);
       deps.Step();) {
    job.add_depends_on(JobId(deps.Int(0)));
  }
  job.set_fabric_key(row.fabric_key);
  for (std::string& key : SplitLines(row.fabric_keys)) job.add_fabric_keys(std::move(key));
  job.set_worker_id(row.worker_id);
  job.set_cancel_requested(row.cancel_requested);
  for (auto blocked = db_->Query("SELECT worker_id FROM job_failed_workers WHERE job_seq = ? AND failures >= ? "
                                 "ORDER BY worker_id",
                                 row.seq, options_.blocklist_after);
       blocked.Step();) {
    job.add_blocklisted_workers(blocked.Text(0));
  }
  return job;
}

void JobQueue::Touch(int64_t seq) {
  db_->Run("UPDATE jobs SET version = ? WHERE seq = ?", ++version_, seq);
}

void JobQueue::WriteLog(int64_t seq, const std::string& line) {
  const std::string text = line.size() <= kMaxLogLineBytes
                               ? line
                               : line.substr(0, kMaxLogLineBytes) + " … (" +
                                     std::to_string(line.size() - kMaxLogLineBytes) + " bytes cut)";
  db_->Run(
      "INSERT INTO job_log (job_seq, line, text) "
      "VALUES (?1, (SELECT COALESCE(MAX(line) + 1, 0) FROM job_log WHERE job_seq = ?1), ?2)",
      seq, text);
  Touch(seq);
  auto total_query = db_->Query("SELECT COALESCE(SUM(LENGTH(CAST(text AS BLOB))), 0) FROM job_log WHERE job_seq = ?",
                                seq);
  total_query.Step();
  int64_t total = total_query.Int(0);
  const int64_t keep = options_.log_keep_bytes;
  if (total <= 2 * keep) return;
  // Over the cap: the head (the first lines within `keep` bytes) stays; the oldest
  // lines after it go until the rest fits in `keep` bytes too.
  int64_t head_bytes = 0;
  int64_t head_end = -1;  // the last line of the head
  std::vector<std::pair<int64_t, int64_t>> tail;  // (line, bytes), oldest first
  for (auto rows = db_->Query("SELECT line, LENGTH(CAST(text AS BLOB)) FROM job_log WHERE job_seq = ? ORDER BY line",
                              seq);
       rows.Step();) {
    if (tail.empty() && rows.Int(0) == head_end + 1 && head_bytes + rows.Int(1) <= keep) {
      head_bytes += rows.Int(1);
      head_end = rows.Int(0);
    } else {
      tail.emplace_back(rows.Int(0), rows.Int(1));
    }
  }
  int64_t drop_through = head_end;
  for (size_t i = 0; i + 1 < tail.size() && total > 2 * keep; ++i) {
    total -= tail[i].second;
    drop_through = tail[i].first;
  }
  db_->Run("DELETE FROM job_log WHERE job_seq = ? AND line > ? AND line <= ?", seq, head_end, drop_through);
}

// --- Transitions (mu_ held, inside a transaction) -----------------------------------

v1::Job JobQueue::InsertJob(const v1::Job& job, int64_t now_ms) {
  std::vector<Row> deps;
  for (const std::string& dep_id : job.depends_on()) {
    auto dep = FindRow(dep_id);
    if (!dep) throw Error(ErrorCode::kNotFound, "depends_on: no job '" + dep_id + "'");
    if (std::none_of(deps.begin(), deps.end(), [&](const Row& d) { return d.seq == dep->seq; })) {
      deps.push_back(std::move(*dep));
    }
  }
  const uint32_t max_attempts = job.max_attempts() ? job.max_attempts() : options_.default_max_attempts;
  auto insert = db_->Query(
      "INSERT INTO jobs (kind, state, priority, max_attempts, payload, client_request_id, fabric_key, "
      "fabric_keys, submitted_ms) VALUES (?, ?, ?, ?, ?, NULLIF(?, ''), ?, ?, ?) RETURNING seq",
      static_cast<int>(job.kind()), static_cast<int>(v1::JOB_STATE_QUEUED), job.priority(), max_attempts,
      PayloadBytes(job), job.client_request_id(), job.fabric_key(), JoinLines(job.fabric_keys()), now_ms);
  insert.Step();
  const int64_t seq = insert.Int(0);
  insert.Run();
  for (const Row& dep : deps) db_->Run("INSERT INTO job_deps (job_seq, dep_seq) VALUES (?, ?)", seq, dep.seq);
  WriteLog(seq, "[queue] submitted");
  for (const Row& dep : deps) {
    if (dep.state == v1::JOB_STATE_FAILED || dep.state == v1::JOB_STATE_CANCELLED) {
      Finish(*FindRow(JobId(seq)), v1::JOB_STATE_FAILED, DependencyError(dep.id(), dep.state, dep.error), now_ms);
      break;
    }
  }
  return ToJob(*FindRow(JobId(seq)));
}

// A lease ended without success: requeue, or end the job if it cannot go on.
QueueCounters& QueueCounters::operator+=(const QueueCounters& other) {
  leases += other.leases;
  lease_expiries += other.lease_expiries;
  stuck_leases += other.stuck_leases;
  failed_attempts += other.failed_attempts;
  retries += other.retries;
  return *this;
}

void JobQueue::EndAttempt(const Row& row, const std::string& error, int64_t now_ms) {
  ++pending_.failed_attempts;
  const std::string attempt =
      "attempt " + std::to_string(row.attempts) + " of " + std::to_string(row.max_attempts);
  if (row.cancel_requested) {
    Finish(row, v1::JOB_STATE_CANCELLED, "cancelled by request", now_ms);
  } else if (row.attempts >= row.max_attempts) {
    WriteLog(row.seq, "[queue] " + attempt + " failed: " + error);
    Finish(row, v1::JOB_STATE_FAILED, error, now_ms);
  } else {
    db_->Run(
        "UPDATE jobs SET state = ?, error = ?, worker_id = '', lease_token = 0, lease_deadline_ms = 0 "
        "WHERE seq = ?",
        static_cast<int>(v1::JOB_STATE_QUEUED), error, row.seq);
    WriteLog(row.seq, "[queue] " + attempt + " failed: " + error + "; requeued");
    ++pending_.retries;
  }
}

void JobQueue::NoteWorkerFailureLocked(const Row& row) {
  db_->Run(
      "INSERT INTO job_failed_workers (job_seq, worker_id, failures) VALUES (?, ?, 1) "
      "ON CONFLICT (job_seq, worker_id) DO UPDATE SET failures = failures + 1",
      row.seq, row.worker_id);
  auto count = db_->Query("SELECT failures FROM job_failed_workers WHERE job_seq = ? AND worker_id = ?", row.seq,
                          row.worker_id);
  count.Step();
  if (count.Int(0) == options_.blocklist_after) {
    WriteLog(row.seq, "[queue] worker " + row.worker_id + " is blocklisted for this job after " +
                          std::to_string(count.Int(0)) + " failure(s); it is not given the job again");
  }
}

void JobQueue::Finish(const Row& row, JobState state, const std::string& error, int64_t now_ms) {
  db_->Run(
      "UPDATE jobs SET state = ?, error = ?, finished_ms = ?, worker_id = '', lease_token = 0, "
      "lease_deadline_ms = 0 WHERE seq = ?",
      static_cast<int>(state), error, now_ms, row.seq);
  WriteLog(row.seq, "[queue] " + StateName(state) + (error.empty() ? "" : ": " + error));
  ended_.emplace_back(row.id(), row.kind);
  if (state == v1::JOB_STATE_FAILED || state == v1::JOB_STATE_CANCELLED) {
    FailDependants(row.seq, DependencyError(row.id(), state, error), now_ms);
  }
}

void JobQueue::FailDependants(int64_t dependency_seq, const std::string& error, int64_t now_ms) {
  const auto dependants =
      Row::Select(*db_, "WHERE state IN (?, ?, ?) AND seq IN (SELECT job_seq FROM job_deps WHERE dep_seq = ?)",
                  static_cast<int>(v1::JOB_STATE_QUEUED), static_cast<int>(v1::JOB_STATE_LEASED),
                  static_cast<int>(v1::JOB_STATE_RUNNING), dependency_seq);
  for (const Row& dependant : dependants) {
    Finish(dependant, v1::JOB_STATE_FAILED, error, now_ms);
  }
}

// --- Submitting -----------------------------------------------------------------------

void JobQueue::CheckSubmission(const v1::Job& job) {
  const bool payload_matches =
      (job.kind() == v1::JOB_KIND_PRECOMPUTE && job.has_precompute()) ||
      (job.kind() == v1::JOB_KIND_RENDER && job.has_render()) ||
      (job.kind() == v1::JOB_KIND_ANIMATE && job.has_animate());
  if (!payload_matches) {
    throw Error(ErrorCode::kInvalidArgument, "job.kind " + v1::JobKind_Name(job.kind()) +
                                                 " needs the matching payload (precompute, render or animate)");
  }
  if (job.max_attempts() > kMaxAttemptsCap) {
    throw Error(ErrorCode::kInvalidArgument,
                "job.max_attempts: " + std::to_string(job.max_attempts()) + " exceeds " + std::to_string(kMaxAttemptsCap));
  }
}

std::optional<v1::Job> JobQueue::FindRetry(const v1::Job& job) const {
  if (job.client_request_id().empty()) return std::nullopt;
  auto existing = db_->Query("SELECT seq FROM jobs WHERE client_request_id = ?", job.client_request_id());
  if (!existing.Step()) return std::nullopt;
  const Row row = RequireRow(JobId(existing.Int(0)));
  if (row.kind != job.kind() || row.payload != PayloadBytes(job)) {
    throw Error(ErrorCode::kInvalidArgument, "client_request_id '" + job.client_request_id() +
                                                 "' was already used for a different job (" + row.id() + ")");
  }
  return ToJob(row);
}

v1::Job JobQueue::Submit(const v1::Job& job) {
  CheckSubmission(job);
  Txn txn(*this);
  if (auto retry = FindRetry(job)) return *retry;
  v1::Job stored = InsertJob(job, clock_.NowMs());
  txn.Commit();
  return stored;
}

v1::Job JobQueue::SubmitDone(const v1::Job& job, const std::vector<std::string>& result_artifacts,
                             const std::string& note) {
  CheckSubmission(job);
  for (size_t i = 0; i < result_artifacts.size(); ++i) {
    CheckArtifactHash(result_artifacts[i], "result_artifacts[" + std::to_string(i) + "]");
  }
  Txn txn(*this);
  if (auto retry = FindRetry(job)) return *retry;
  const int64_t now = clock_.NowMs();
  const v1::Job inserted = InsertJob(job, now);
  const Row row = RequireRow(inserted.id());
  db_->Run("UPDATE jobs SET results = ?, progress_fraction = 1, progress_stage = 'done', started_ms = ? WHERE seq = ?",
           JoinLines(result_artifacts), now, row.seq);
  WriteLog(row.seq, "[queue] " + note);
  Finish(row, v1::JOB_STATE_SUCCEEDED, "", now);
  v1::Job stored = ToJob(RequireRow(inserted.id()));
  txn.Commit();
  return stored;
}

v1::Job JobQueue::SubmitPrecomputeOnce(const v1::PrecomputeJob& precompute, const std::string& fabric_key,
                                       int32_t priority) {
  CheckArtifactHash(fabric_key, "fabric_key");
  Txn txn(*this);
  auto active = db_->Query(
      "SELECT seq FROM jobs WHERE fabric_key = ? AND kind = ? AND state IN (?, ?, ?) ORDER BY seq LIMIT 1",
      fabric_key, static_cast<int>(v1::JOB_KIND_PRECOMPUTE), static_cast<int>(v1::JOB_STATE_QUEUED),
      static_cast<int>(v1::JOB_STATE_LEASED), static_cast<int>(v1::JOB_STATE_RUNNING));
  if (active.Step()) {
    const int64_t seq = active.Int(0);
    db_->Run("UPDATE jobs SET priority = ? WHERE seq = ? AND state = ? AND priority < ?", priority, seq,
             static_cast<int>(v1::JOB_STATE_QUEUED), priority);
    if (db_->Changes() > 0) Touch(seq);
    v1::Job joined = ToJob(RequireRow(JobId(seq)));
    txn.Commit();
    return joined;
  }
  v1::Job job;
  job.set_kind(v1::JOB_KIND_PRECOMPUTE);
  job.set_priority(priority);
  job.set_fabric_key(fabric_key);
  *job.mutable_precompute() = precompute;
  v1::Job stored = InsertJob(job, clock_.NowMs());
  txn.Commit();
  return stored;
}

// --- Workers --------------------------------------------------------------------------

std::optional<JobLease> JobQueue::LeaseLocked(const std::string& worker_id) {
  auto next = db_->Query(
      "SELECT seq FROM jobs j WHERE state = ?1 "
      "AND NOT EXISTS (SELECT 1 FROM job_deps d JOIN jobs p ON p.seq = d.dep_seq "
      "                WHERE d.job_seq = j.seq AND p.state != ?2) "
      // Not a job this worker failed, unless no other live worker that has not
      // failed it could take it.
      // Never a job this worker is blocklisted from.
      "AND NOT EXISTS (SELECT 1 FROM job_failed_workers b WHERE b.job_seq = j.seq AND b.worker_id = ?3 "
      "                AND b.failures >= ?5) "
      "AND NOT (EXISTS (SELECT 1 FROM job_failed_workers f WHERE f.job_seq = j.seq AND f.worker_id = ?3) "
      "         AND EXISTS (SELECT 1 FROM temp.live_workers l WHERE l.worker_id != ?3 AND l.seen_ms > ?4 "
      "                     AND l.worker_id NOT IN (SELECT worker_id FROM job_failed_workers g "
      "                                             WHERE g.job_seq = j.seq))) "
      "ORDER BY priority DESC, seq LIMIT 1",
      static_cast<int>(v1::JOB_STATE_QUEUED), static_cast<int>(v1::JOB_STATE_SUCCEEDED), worker_id,
      clock_.NowMs() - options_.lease_duration_ms, options_.blocklist_after);
  NoteWorkerLocked(worker_id, clock_.NowMs());
  if (!next.Step()) return std::nullopt;
  const int64_t seq = next.Int(0);
  const int64_t now = clock_.NowMs();
  auto lease = db_->Query("INSERT INTO leases (job_seq, worker_id, leased_ms) VALUES (?, ?, ?) RETURNING token",
                          seq, worker_id, now);
  lease.Step();
  const auto token = static_cast<uint64_t>(lease.Int(0));
  lease.Run();
  const int64_t deadline = now + options_.lease_duration_ms;
  db_->Run(
      "UPDATE jobs SET state = ?, attempts = attempts + 1, worker_id = ?, lease_token = ?, "
      "lease_deadline_ms = ?, progress_moved_ms = ?, started_ms = ?, progress_fraction = 0, "
      "progress_stage = '' WHERE seq = ?",
      static_cast<int>(v1::JOB_STATE_LEASED), worker_id, token, deadline, now, now, seq);
  const Row row = RequireRow(JobId(seq));
  WriteLog(seq, "[queue] leased by worker " + worker_id + " (attempt " + std::to_string(row.attempts) + " of " +
                    std::to_string(row.max_attempts) + ")");
  ++pending_.leases;
  return JobLease{ToJob(row), token, deadline};
}

void JobQueue::NoteWorkerLocked(const std::string& worker_id, int64_t now_ms) {
  db_->Run("INSERT OR REPLACE INTO temp.live_workers (worker_id, seen_ms) VALUES (?, ?)", worker_id, now_ms);
}

void JobQueue::WorkerSeen(const std::string& worker_id) {
  if (worker_id.empty()) throw Error(ErrorCode::kInvalidArgument, "worker_id is empty");
  Txn txn(*this);
  NoteWorkerLocked(worker_id, clock_.NowMs());
  txn.Commit();
}

std::optional<JobLease> JobQueue::Lease(const std::string& worker_id) {
  if (worker_id.empty()) throw Error(ErrorCode::kInvalidArgument, "worker_id is empty");
  Txn txn(*this);
  auto lease = LeaseLocked(worker_id);
  txn.Commit();  // the worker was seen, leased or not
  return lease;
}

std::optional<JobLease> JobQueue::LeaseWait(const std::string& worker_id,
                                            std::chrono::steady_clock::time_point deadline) {
  while (true) {
    uint64_t seen = 0;
    {
      std::lock_guard lock(mu_);
      if (shutdown_) return std::nullopt;
      seen = version_;
    }
    if (auto lease = Lease(worker_id)) return lease;
    std::unique_lock lock(mu_);
    if (!changed_.wait_until(lock, deadline, [&] { return shutdown_ || version_ != seen; })) return std::nullopt;
  }
}

HeartbeatStatus JobQueue::Heartbeat(const std::string& id, uint64_t token, double fraction,
                                    const std::string& stage) {
  if (!(fraction >= 0 && fraction <= 1)) {
    throw Error(ErrorCode::kInvalidArgument, "progress fraction " + std::to_string(fraction) + " is not in [0, 1]");
  }
  Txn txn(*this);
  const Row row = RequireRow(id);
  if (!row.leased() || row.lease_token != token) return HeartbeatStatus::kStaleToken;
  const int64_t now = clock_.NowMs();
  NoteWorkerLocked(row.worker_id, now);
  const bool moved = fraction != row.progress_fraction || stage != row.progress_stage;
  db_->Run(
      "UPDATE jobs SET state = ?, progress_fraction = ?, progress_stage = ?, lease_deadline_ms = ?, "
      "progress_moved_ms = ? WHERE seq = ?",
      static_cast<int>(v1::JOB_STATE_RUNNING), fraction, stage, now + options_.lease_duration_ms,
      moved ? now : row.progress_moved_ms, row.seq);
  Touch(row.seq);
  txn.Commit();
  return row.cancel_requested ? HeartbeatStatus::kCancelRequested : HeartbeatStatus::kOk;
}

void JobQueue::CheckLease(const std::string& id, uint64_t token) const {
  std::lock_guard lock(mu_);
  RequireLease(id, token);
}

v1::Job JobQueue::Complete(const std::string& id, uint64_t token, const std::vector<std::string>& result_artifacts,
                           double run_ms) {
  if (!(run_ms >= 0)) throw Error(ErrorCode::kInvalidArgument, "run_ms " + std::to_string(run_ms) + " is negative");
  for (size_t i = 0; i < result_artifacts.size(); ++i) {
    CheckArtifactHash(result_artifacts[i], "result_artifacts[" + std::to_string(i) + "]");
  }
  Txn txn(*this);
  const Row row = RequireLease(id, token);
  const int64_t now = clock_.NowMs();
  NoteWorkerLocked(row.worker_id, now);
  if (row.cancel_requested) {
    Finish(row, v1::JOB_STATE_CANCELLED, "cancelled by request (the finished results were discarded)", now);
  } else {
    db_->Run("UPDATE jobs SET results = ?, progress_fraction = 1, progress_stage = 'done', run_ms = ? WHERE seq = ?",
             JoinLines(result_artifacts), run_ms, row.seq);
    Finish(row, v1::JOB_STATE_SUCCEEDED, "", now);
  }
  v1::Job job = ToJob(RequireRow(id));
  txn.Commit();
  return job;
}

v1::Job JobQueue::Fail(const std::string& id, uint64_t token, const std::string& error, Failure failure) {
  Txn txn(*this);
  const Row row = RequireLease(id, token);
  const int64_t now = clock_.NowMs();
  NoteWorkerLocked(row.worker_id, now);
  NoteWorkerFailureLocked(row);
  const std::string message =
      (error.empty() ? "worker reported a failure without a message" : error) + " (worker " + row.worker_id + ")";
  if (failure == Failure::kPermanent && !row.cancel_requested) {
    WriteLog(row.seq, "[queue] attempt " + std::to_string(row.attempts) + " failed permanently (bad input, not retried): " +
                          message);
    Finish(row, v1::JOB_STATE_FAILED, message, now);
  } else {
    EndAttempt(row, message, now);
  }
  v1::Job job = ToJob(RequireRow(id));
  txn.Commit();
  return job;
}

v1::Job JobQueue::HandBack(const std::string& id, uint64_t token, const std::string& reason,
                           const std::string& wait_for) {
  Txn txn(*this);
  const Row row = RequireLease(id, token);
  const int64_t now = clock_.NowMs();  // (the worker is not noted live: it is going away)
  if (row.cancel_requested) {
    Finish(row, v1::JOB_STATE_CANCELLED, "cancelled by request", now);
  } else {
    db_->Run(
        "UPDATE jobs SET state = ?, attempts = attempts - 1, worker_id = '', lease_token = 0, lease_deadline_ms = 0 "
        "WHERE seq = ?",
        static_cast<int>(v1::JOB_STATE_QUEUED), row.seq);
    const std::optional<Row> dependency = wait_for.empty() ? std::nullopt : std::optional(RequireRow(wait_for));
    if (dependency) db_->Run("INSERT INTO job_deps (job_seq, dep_seq) VALUES (?, ?)", row.seq, dependency->seq);
    WriteLog(row.seq, "[queue] handed back by worker " + row.worker_id + " (" + reason + "); requeued" +
                          (dependency ? " to wait for " + wait_for : "") + ", the attempt not counted");
    if (dependency && (dependency->state == v1::JOB_STATE_FAILED || dependency->state == v1::JOB_STATE_CANCELLED)) {
      Finish(*FindRow(id), v1::JOB_STATE_FAILED, DependencyError(wait_for, dependency->state, dependency->error), now);
    }
  }
  v1::Job job = ToJob(RequireRow(id));
  txn.Commit();
  return job;
}

int JobQueue::RequeueExpired() {
  Txn txn(*this);
  const int64_t now = clock_.NowMs();
  const auto ended = Row::Select(
      *db_, "WHERE state IN (?, ?) AND (lease_deadline_ms <= ? OR progress_moved_ms <= ?) ORDER BY seq",
      static_cast<int>(v1::JOB_STATE_LEASED), static_cast<int>(v1::JOB_STATE_RUNNING), now,
      now - options_.stuck_after_ms);
  for (const Row& row : ended) {
    ++(row.lease_deadline_ms <= now ? pending_.lease_expiries : pending_.stuck_leases);
    const std::string reason =
        row.lease_deadline_ms <= now
            ? "lease expired: worker " + row.worker_id + " sent no heartbeat for " +
                  Seconds(now - row.lease_deadline_ms + options_.lease_duration_ms)
            : "stuck: no progress for " + Seconds(now - row.progress_moved_ms) + " on worker " + row.worker_id;
    NoteWorkerFailureLocked(row);
    EndAttempt(row, reason, now);
  }
  txn.Commit();
  return static_cast<int>(ended.size());
}

// --- Clients --------------------------------------------------------------------------

v1::Job JobQueue::Cancel(const std::string& id) {
  Txn txn(*this);
  const Row row = RequireRow(id);
  if (IsTerminal(row.state)) {
    throw Error(ErrorCode::kFailedPrecondition, "job " + id + " is already " + StateName(row.state));
  }
  if (row.state == v1::JOB_STATE_QUEUED) {
    Finish(row, v1::JOB_STATE_CANCELLED, "cancelled by request", clock_.NowMs());
  } else if (!row.cancel_requested) {
    db_->Run("UPDATE jobs SET cancel_requested = 1 WHERE seq = ?", row.seq);
    WriteLog(row.seq, "[queue] cancel requested; worker " + row.worker_id + " learns it at its next heartbeat");
  }
  v1::Job job = ToJob(RequireRow(id));
  txn.Commit();
  return job;
}

v1::Job JobQueue::SetPriority(const std::string& id, int32_t priority) {
  Txn txn(*this);
  const Row row = RequireRow(id);
  if (IsTerminal(row.state)) {
    throw Error(ErrorCode::kFailedPrecondition, "job " + id + " is already " + StateName(row.state));
  }
  if (row.priority != priority) {
    db_->Run("UPDATE jobs SET priority = ? WHERE seq = ?", priority, row.seq);
    WriteLog(row.seq, "[queue] priority " + std::to_string(row.priority) + " -> " + std::to_string(priority));
  }
  v1::Job job = ToJob(RequireRow(id));
  txn.Commit();
  return job;
}

void JobQueue::RetryLocked(const Row& row, std::vector<int64_t>& retried) {
  for (auto deps = db_->Query("SELECT dep_seq FROM job_deps WHERE job_seq = ?", row.seq); deps.Step();) {
    const Row dep = RequireRow(JobId(deps.Int(0)));
    if (dep.state == v1::JOB_STATE_FAILED || dep.state == v1::JOB_STATE_CANCELLED) {
      RetryLocked(dep, retried);
      retried.push_back(dep.seq);
    }
  }
  db_->Run(
      "UPDATE jobs SET state = ?, attempts = 0, error = '', cancel_requested = 0, worker_id = '', lease_token = 0, "
      "lease_deadline_ms = 0, started_ms = 0, finished_ms = 0, progress_fraction = 0, progress_stage = '', "
      "results = '', run_ms = 0 WHERE seq = ?",
      static_cast<int>(v1::JOB_STATE_QUEUED), row.seq);
  db_->Run("DELETE FROM job_failed_workers WHERE job_seq = ?", row.seq);
  WriteLog(row.seq, "[queue] retried by request (was " + StateName(row.state) +
                        "); attempts and blocklist reset");
}

std::vector<v1::Job> JobQueue::Retry(const std::vector<std::string>& ids) {
  Txn txn(*this);
  std::vector<Row> rows;
  for (const std::string& id : ids) {
    Row row = RequireRow(id);
    if (row.state != v1::JOB_STATE_FAILED && row.state != v1::JOB_STATE_CANCELLED) {
      throw Error(ErrorCode::kFailedPrecondition,
                  "job " + id + " is " + StateName(row.state) + ": only FAILED or CANCELLED jobs are retried");
    }
    rows.push_back(std::move(row));
  }
  std::vector<int64_t> dependencies;
  std::vector<int64_t> asked;
  for (const Row& row : rows) {
    if (std::find(asked.begin(), asked.end(), row.seq) != asked.end()) continue;
    // A job asked for may already have been retried as another's dependency.
    if (std::find(dependencies.begin(), dependencies.end(), row.seq) == dependencies.end()) {
      RetryLocked(RequireRow(row.id()), dependencies);
    }
    asked.push_back(row.seq);
  }
  std::vector<v1::Job> jobs;
  for (const int64_t seq : asked) jobs.push_back(ToJob(RequireRow(JobId(seq))));
  for (const int64_t seq : dependencies) {
    if (std::find(asked.begin(), asked.end(), seq) == asked.end()) jobs.push_back(ToJob(RequireRow(JobId(seq))));
  }
  txn.Commit();
  return jobs;
}

std::vector<v1::Job> JobQueue::Delete(const std::vector<std::string>& ids) {
  Txn txn(*this);
  std::vector<v1::Job> deleted;
  for (const std::string& id : ids) {
    const Row row = RequireRow(id);
    if (!IsTerminal(row.state)) {
      throw Error(ErrorCode::kFailedPrecondition,
                  "job " + id + " is " + StateName(row.state) + ": only finished jobs are deleted (cancel it first)");
    }
    auto waiting = db_->Query(
        "SELECT j.seq FROM job_deps d JOIN jobs j ON j.seq = d.job_seq WHERE d.dep_seq = ? AND j.state IN (?, ?, ?) "
        "LIMIT 1",
        row.seq, static_cast<int>(v1::JOB_STATE_QUEUED), static_cast<int>(v1::JOB_STATE_LEASED),
        static_cast<int>(v1::JOB_STATE_RUNNING));
    if (waiting.Step()) {
      throw Error(ErrorCode::kFailedPrecondition,
                  "job " + id + ": unfinished job " + JobId(waiting.Int(0)) + " depends on it");
    }
    if (std::none_of(deleted.begin(), deleted.end(), [&](const v1::Job& job) { return job.id() == id; })) {
      deleted.push_back(ToJob(row));
    }
  }
  for (const v1::Job& job : deleted) {
    const int64_t seq = *ParseJobId(job.id());
    db_->Run("DELETE FROM job_log WHERE job_seq = ?", seq);
    db_->Run("DELETE FROM job_failed_workers WHERE job_seq = ?", seq);
    db_->Run("DELETE FROM job_deps WHERE job_seq = ?1 OR dep_seq = ?1", seq);
    db_->Run("DELETE FROM leases WHERE job_seq = ?", seq);  // tokens still only grow (AUTOINCREMENT)
    db_->Run("DELETE FROM jobs WHERE seq = ?", seq);
  }
  ++version_;
  txn.Commit();
  return deleted;
}

v1::Job JobQueue::Get(const std::string& id) const {
  std::lock_guard lock(mu_);
  return ToJob(RequireRow(id));
}

JobPage JobQueue::List(const JobFilter& filter, int page_size, const std::string& page_token,
                       uint64_t max_bytes) const {
  if (page_size <= 0) page_size = kDefaultPageSize;
  page_size = std::min(page_size, kMaxPageSize);
  std::optional<int64_t> before;
  if (!page_token.empty()) {
    before = ParseJobId(page_token);
    if (!before) throw Error(ErrorCode::kInvalidArgument, "page_token '" + page_token + "' is not one this server gave");
  }
  const auto placeholders = [](size_t n) {
    std::string text;
    for (size_t i = 0; i < n; ++i) text += i ? ", ?" : "?";
    return text;
  };
  std::string sql = std::string("SELECT ") + kRowColumns + " FROM jobs WHERE TRUE";  // bound one by one below
  if (!filter.states.empty()) sql += " AND state IN (" + placeholders(filter.states.size()) + ")";
  if (!filter.kinds.empty()) sql += " AND kind IN (" + placeholders(filter.kinds.size()) + ")";
  if (before) sql += " AND seq < ?";
  sql += " ORDER BY seq DESC LIMIT ?";

  std::lock_guard lock(mu_);
  std::vector<SqlValue> values;
  for (const JobState state : filter.states) values.push_back(int64_t{state});
  for (const v1::JobKind kind : filter.kinds) values.push_back(int64_t{kind});
  if (before) values.push_back(*before);
  values.push_back(int64_t{page_size} + 1);
  SqlQuery query(db_->Execute(sql, values));
  JobPage page;
  std::optional<int64_t> last_seq;
  uint64_t bytes = 0;
  while (query.Step()) {
    const Row row = Row::Read(query);
    v1::Job job = ToJob(row);
    bytes += job.ByteSizeLong();
    if (static_cast<int>(page.jobs.size()) == page_size || (max_bytes > 0 && bytes > max_bytes && last_seq)) {
      page.next_page_token = JobId(*last_seq);
      break;
    }
    page.jobs.push_back(std::move(job));
    last_seq = row.seq;
  }
  return page;
}

QueueDepth JobQueue::Depth() const {
  std::lock_guard lock(mu_);
  QueueDepth depth;
  const auto known = [](int64_t state, int64_t kind) {
    return state >= 0 && state < v1::JobState_ARRAYSIZE && kind >= 0 && kind < v1::JobKind_ARRAYSIZE;
  };
  for (auto query = db_->Query("SELECT state, kind, COUNT(*) FROM jobs GROUP BY state, kind"); query.Step();) {
    const int64_t state = query.Int(0), kind = query.Int(1), count = query.Int(2);
    if (!known(state, kind)) continue;
    depth.by_state[state] += count;
    depth.by_state_kind[state][kind] = count;
  }
  for (auto ready = db_->Query(
           "SELECT kind, COUNT(*) FROM jobs j WHERE state = ?1 AND NOT EXISTS (SELECT 1 FROM job_deps d "
           "JOIN jobs p ON p.seq = d.dep_seq WHERE d.job_seq = j.seq AND p.state != ?2) GROUP BY kind",
           static_cast<int>(v1::JOB_STATE_QUEUED), static_cast<int>(v1::JOB_STATE_SUCCEEDED));
       ready.Step();) {
    const int64_t kind = ready.Int(0), count = ready.Int(1);
    if (!known(v1::JOB_STATE_QUEUED, kind)) continue;
    depth.ready += count;
    depth.ready_by_kind[kind] = count;
  }
  return depth;
}

QueueCounters JobQueue::Counters() const {
  std::lock_guard lock(mu_);
  return counters_;
}

void JobQueue::AppendLog(const std::string& id, const std::string& line) {
  Txn txn(*this);
  WriteLog(RequireRow(id).seq, line);
  txn.Commit();
}

std::vector<std::string> JobQueue::Log(const std::string& id, int64_t from_line, int64_t* next_line) const {
  if (from_line < 0) throw Error(ErrorCode::kInvalidArgument, "from_line " + std::to_string(from_line) + " is negative");
  std::lock_guard lock(mu_);
  std::vector<std::string> lines;
  int64_t expected = from_line;
  for (auto query = db_->Query("SELECT line, text FROM job_log WHERE job_seq = ? AND line >= ? ORDER BY line",
                               RequireRow(id).seq, from_line);
       query.Step();) {
    const int64_t line = query.Int(0);
    if (line > expected) {
      lines.push_back("… " + std::to_string(line - expected) + " log line(s) truncated (a job's log keeps its first and last " +
                      std::to_string(options_.log_keep_bytes >> 10) + " KiB) …");
    }
    lines.push_back(query.Text(1));
    expected = line + 1;
  }
  if (next_line) *next_line = expected;
  return lines;
}

// --- Watching -------------------------------------------------------------------------

uint64_t JobQueue::Version() const {
  std::lock_guard lock(mu_);
  return version_;
}

std::optional<uint64_t> JobQueue::WaitForChange(const std::string& id, uint64_t seen_version,
                                                std::chrono::steady_clock::time_point deadline) const {
  std::unique_lock lock(mu_);
  const std::optional<int64_t> seq = id.empty() ? std::nullopt : std::optional(RequireRow(id).seq);
  const auto changed = [&] {
    if (!seq) return version_ > seen_version;
    auto query = db_->Query("SELECT version FROM jobs WHERE seq = ?", *seq);
    return query.Step() && static_cast<uint64_t>(query.Int(0)) > seen_version;
  };
  if (!changed_.wait_until(lock, deadline, [&] { return shutdown_ || changed(); }) || shutdown_) {
    return std::nullopt;
  }
  return version_;
}

void JobQueue::OnJobEnded(std::function<void(const std::string& id, v1::JobKind kind)> listener) {
  std::vector<std::pair<std::string, v1::JobKind>> unheard;
  {
    std::lock_guard lock(mu_);
    on_ended_ = listener;
    unheard = std::exchange(unheard_, {});
  }
  for (const auto& [id, kind] : unheard) listener(id, kind);
}

void JobQueue::Shutdown() {
  std::lock_guard lock(mu_);
  shutdown_ = true;
  changed_.notify_all();
}

}  // namespace loom::server
