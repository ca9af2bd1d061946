#include "worker/worker_loop.h"

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <thread>
#include <vector>

#include "core/util/error.h"
#include "rpc/artifact_transfer.h"
#include "rpc/channel.h"
#include "rpc/status.h"
#include "worker/job_runner.h"

namespace loom::worker {
namespace {

using namespace std::chrono_literals;

constexpr std::chrono::milliseconds kFirstBackoff = 100ms;
constexpr std::chrono::milliseconds kMaxBackoff = 5000ms;
// Fitted fabrics kept between render jobs (a worker often renders one fabric many times).
constexpr size_t kKeptFits = 4;
// Moved progress reaches the server within this (issue 22: WatchJob shows it live).
constexpr std::chrono::milliseconds kProgressPeriod = 1000ms;

// Why a job stops before it is done.
enum class Interruption { kNone, kCancelled, kLeaseLost, kStopping };

// Thrown from core's progress callback to abandon a job; the lease says why.
struct JobInterrupted {};

v1::WorkerCapabilities Capabilities(const gl::DeviceInfo& device, const std::string& label) {
  v1::WorkerCapabilities capabilities;
  capabilities.set_gl_vendor(device.gl_vendor);
  capabilities.set_gl_renderer(device.gl_renderer);
  capabilities.set_gl_version(device.gl_version);
  capabilities.set_software_gl(device.software);
  capabilities.set_cores(std::thread::hardware_concurrency());
  capabilities.set_memory_bytes(static_cast<uint64_t>(sysconf(_SC_PHYS_PAGES)) *
                                static_cast<uint64_t>(sysconf(_SC_PAGE_SIZE)));
  char host[256] = {};
  gethostname(host, sizeof host - 1);
  capabilities.set_hostname(std::string(host) + "/" + label);
  return capabilities;
}

// The part of a progress stage before its counter ("acquisition: view 3/64" ->
// "acquisition"): a new one is worth a log line, a new count is not.
std::string_view StageName(std::string_view stage) { return stage.substr(0, stage.find(':')); }

}  // namespace

// One leased job: what the heartbeat thread reports (progress, new log lines) and
// what it learns (cancel, lost lease); Stop() interrupts it too.
class WorkerLoop::Lease {
 public:
  Lease(WorkerLoop& loop, const v1::LeaseJobResponse& leased)
      : loop_(loop), job_id_(leased.job().id()), token_(leased.fencing_token()) {
    heartbeat_ = std::thread([this] { HeartbeatLoop(); });
  }
  ~Lease() {
    {
      std::lock_guard lock(mu_);
      done_ = true;
    }
    wake_.notify_all();
    heartbeat_.join();
  }

  const std::string& job_id() const { return job_id_; }
  uint64_t token() const { return token_; }

  // Core's progress callback for a precompute: records progress; throws
  // JobInterrupted once the job must stop.
  void Progress(double fraction, std::string_view stage) {
    if (Record(fraction, stage) != Interruption::kNone) throw JobInterrupted{};
  }
  // The same for a render, which runs to the end when the worker is stopping: only
  // a cancel or a lost lease abandons it.
  void RenderProgress(double fraction, std::string_view stage) {
    const Interruption why = Record(fraction, stage);
    if (why == Interruption::kCancelled || why == Interruption::kLeaseLost) throw JobInterrupted{};
  }
  void Log(std::string line) {
    std::lock_guard lock(mu_);
    log_.push_back(std::move(line));
  }
  void Interrupt(Interruption why) {
    std::lock_guard lock(mu_);
    if (interruption_ == Interruption::kNone) interruption_ = why;
  }
  Interruption interruption() {
    std::lock_guard lock(mu_);
    return interruption_;
  }
  std::vector<std::string> TakeLog() {
    std::lock_guard lock(mu_);
    return std::exchange(log_, {});
  }

 private:
  // Records progress for the next heartbeat and marks the worker alive; returns
  // why the job must stop, if it must. A new stage wakes the heartbeat thread at
  // once, moved progress within a second (HeartbeatLoop).
  Interruption Record(double fraction, std::string_view stage) {
    // The stage's name, not its counter: the alive state changes a few times a job.
    loop_.MarkAlive("job " + job_id_ + ": " + std::string(StageName(stage)));
    std::lock_guard lock(mu_);
    const bool new_stage = StageName(stage) != StageName(progress_.stage());
    if (new_stage) log_.push_back(std::string(StageName(stage)));
    const bool moved = fraction != progress_.fraction() || stage != progress_.stage();
    progress_.set_fraction(fraction);
    progress_.set_stage(std::string(stage));
    if (new_stage || (moved && !moved_)) wake_.notify_all();
    urgent_ = urgent_ || new_stage;
    moved_ = moved_ || moved;
    return interruption_;
  }

  // Heartbeats carry progress to the server (and so to WatchJob): at once when the
  // lease begins and when a stage begins, within kProgressPeriod when the progress
  // moved, and every heartbeat interval regardless, which keeps the lease.
  void HeartbeatLoop() {
    using Clock = std::chrono::steady_clock;
    std::unique_lock lock(mu_);
    Clock::time_point last_sent = Clock::now();
    while (!done_) {
      const auto period = moved_ ? std::min(kProgressPeriod, loop_.heartbeat_interval_) : loop_.heartbeat_interval_;
      if (!urgent_ && Clock::now() < last_sent + period) {
        wake_.wait_until(lock, last_sent + period);  // or woken by Record or the end
        continue;
      }
      urgent_ = moved_ = false;
      last_sent = Clock::now();
      v1::HeartbeatRequest request;
      request.set_worker_id(loop_.worker_id_);
      request.set_job_id(job_id_);
      request.set_fencing_token(token_);
      *request.mutable_progress() = progress_;
      for (std::string& line : log_) request.add_log_lines(std::move(line));
      log_.clear();
      lock.unlock();
      grpc::ClientContext context;
      context.set_deadline(rpc::DeadlineIn(loop_.heartbeat_interval_));
      v1::HeartbeatResponse response;
      const grpc::Status status = loop_.stub_->Heartbeat(&context, request, &response);
      lock.lock();
      if (!status.ok()) {
        // The lease outlives a few lost heartbeats; keep the lines for the next one.
        spdlog::warn("{}: heartbeat for job {}: {}", loop_.options_.label, job_id_, status.error_message());
        log_.insert(log_.begin(), request.log_lines().begin(), request.log_lines().end());
        continue;
      }
      if (response.action() == v1::HeartbeatResponse::ACTION_CANCEL && interruption_ == Interruption::kNone) {
        interruption_ = Interruption::kCancelled;
      }
      if (response.action() == v1::HeartbeatResponse::ACTION_LEASE_LOST) interruption_ = Interruption::kLeaseLost;
    }
  }

  WorkerLoop& loop_;
  const std::string job_id_;
  const uint64_t token_;
  std::mutex mu_;
  std::condition_variable wake_;
  bool done_ = false;
  bool urgent_ = true;  // send at once: the lease began, or a stage did
  bool moved_ = false;  // the progress moved since the last heartbeat
  v1::JobProgress progress_;
  std::vector<std::string> log_;
  Interruption interruption_ = Interruption::kNone;
  std::thread heartbeat_;
};

// Fabric assets by key, the few most recently used.
class WorkerLoop::FitCache {
 public:
  const FabricAsset& Get(const v1::FabricAsset& asset, JobRunner& runner, v1::WorkerService::Stub& stub) {
    const auto found =
        std::find_if(fits_.begin(), fits_.end(), [&](const auto& e) { return e.first == asset.fabric_key(); });
    if (found != fits_.end()) {
      std::rotate(fits_.begin(), found, found + 1);
      return *fits_.front().second;
    }
    std::vector<NamedFile> files;
    for (const v1::ArtifactRef& file : asset.files()) {
      files.push_back({file.name(), rpc::DownloadArtifact(stub, file.sha256())});  // damaged: kInternal, retried
    }
    fits_.emplace(fits_.begin(), asset.fabric_key(), runner.ReadAsset(files));
    if (fits_.size() > kKeptFits) fits_.pop_back();
    return *fits_.front().second;
  }

 private:
  std::vector<std::pair<std::string, std::unique_ptr<FabricAsset>>> fits_;  // most recent first
};

WorkerLoop::WorkerLoop(std::shared_ptr<grpc::Channel> channel, WorkerOptions options)
    : channel_(std::move(channel)), stub_(v1::WorkerService::NewStub(channel_)), options_(std::move(options)) {}

WorkerLoop::~WorkerLoop() = default;

void WorkerLoop::Stop() {
  std::lock_guard lock(mu_);
  stopping_ = true;
  if (pending_lease_ != nullptr) pending_lease_->TryCancel();
  if (current_ != nullptr) current_->Interrupt(Interruption::kStopping);
  wake_.notify_all();
}

void WorkerLoop::Register(const gl::DeviceInfo& device) {
  v1::RegisterWorkerRequest request;
  *request.mutable_capabilities() = Capabilities(device, options_.label);
  grpc::ClientContext context;
  context.set_deadline(rpc::DeadlineIn(10s));
  v1::RegisterWorkerResponse response;
  rpc::ThrowIfFailed(stub_->RegisterWorker(&context, request, &response), "RegisterWorker");
  worker_id_ = response.worker_id();
  heartbeat_interval_ = std::chrono::milliseconds(std::max<uint32_t>(response.heartbeat_interval_ms(), 50));
  spdlog::info("{}: registered as {} (heartbeat every {} ms)", options_.label, worker_id_, heartbeat_interval_.count());
}

void WorkerLoop::MarkAlive(std::string_view state) const {
  if (options_.alive) options_.alive(state);
}

void WorkerLoop::Backoff(std::chrono::milliseconds& delay) {
  MarkAlive("server unreachable, retrying");
  std::unique_lock lock(mu_);
  wake_.wait_for(lock, delay, [this] { return stopping_.load(); });
  delay = std::min(delay * 2, kMaxBackoff);
}

void WorkerLoop::Run() {
  JobRunner runner(options_.gl);
  spdlog::info("{}: GL {} | {}", options_.label, runner.device().gl_vendor, runner.device().gl_renderer);
  MarkAlive("started");
  FitCache fits;
  std::chrono::milliseconds delay = kFirstBackoff;
  while (!stopping_) {
    try {
      if (worker_id_.empty()) Register(runner.device());
      MarkAlive("waiting for work");
      const std::optional<v1::LeaseJobResponse> leased = LeaseJob();
      delay = kFirstBackoff;
      if (leased) RunJob(runner, fits, *leased);
    } catch (const Error& error) {
      if (stopping_) break;
      if (error.code() != ErrorCode::kUnavailable) throw;
      spdlog::warn("{}: {}; retrying in {} ms", options_.label, error.what(), delay.count());
      Backoff(delay);
      worker_id_.clear();  // a restarted server has forgotten this worker
    }
  }
  spdlog::info("{}: stopped after {} job(s)", options_.label, completed_jobs_.load());
}

std::optional<v1::LeaseJobResponse> WorkerLoop::LeaseJob() {
  v1::LeaseJobRequest request;
  request.set_worker_id(worker_id_);
  request.set_wait_ms(static_cast<uint32_t>(options_.lease_wait.count()));
  grpc::ClientContext context;
  context.set_deadline(rpc::DeadlineIn(options_.lease_wait + 10s));
  {
    std::lock_guard lock(mu_);
    if (stopping_) return std::nullopt;
    pending_lease_ = &context;
  }
  v1::LeaseJobResponse response;
  const grpc::Status status = stub_->LeaseJob(&context, request, &response);
  {
    std::lock_guard lock(mu_);
    pending_lease_ = nullptr;
  }
  if (stopping_) return std::nullopt;
  if (status.error_code() == grpc::StatusCode::NOT_FOUND) {
    spdlog::info("{}: the server does not know worker {} (it restarted?); registering again", options_.label,
                 worker_id_);
    worker_id_.clear();
    return std::nullopt;
  }
  rpc::ThrowIfFailed(status, "LeaseJob");
  if (!response.has_job()) return std::nullopt;
  return response;
}

std::vector<NamedFile> WorkerLoop::Execute(JobRunner& runner, FitCache& fits, const v1::LeaseJobResponse& leased,
                                           Lease& lease, double& run_ms) {
  const v1::Job& job = leased.job();
  if (options_.before_job) options_.before_job(job);
  const auto timed = [&run_ms](auto&& work) {
    const auto start = std::chrono::steady_clock::now();
    auto result = work();
    run_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return result;
  };
  if (job.has_precompute()) {
    return timed([&] {
      return runner.Precompute(job.precompute(), job.fabric_key(),
                               [&lease](double fraction, std::string_view stage) { lease.Progress(fraction, stage); });
    });
  }
  const MeshTextResolver meshes = [this](const v1::MeshRef& mesh, const TextSink& consume) {
    if (mesh.source_case() != v1::MeshRef::kArtifact) {
      throw Error(ErrorCode::kInvalidArgument, "a worker reads uploaded mesh artifacts only");
    }
    // Streamed into the parser: a mesh upload may be large (server/job_service.h).
    rpc::DownloadArtifactInPieces(*stub_, mesh.artifact(), consume);
  };
  if (job.has_animate()) {
    return {timed([&] {
      return runner.Animate(job.animate(), meshes,
                            [&lease](double fraction, std::string_view stage) { lease.Progress(fraction, stage); });
    })};
  }
  FabricAssets fitted;
  for (const v1::FabricAsset& asset : leased.fabrics()) fitted[asset.fabric_key()] = &fits.Get(asset, runner, *stub_);
  return {timed([&] {
    return runner.Render(job.render(), meshes, fitted,
                         [&lease](double fraction, std::string_view stage) { lease.RenderProgress(fraction, stage); });
  })};
}

void WorkerLoop::RunJob(JobRunner& runner, FitCache& fits, const v1::LeaseJobResponse& leased) {
  const v1::Job& job = leased.job();
  const char* kind = job.has_precompute() ? "precompute" : job.has_animate() ? "animate" : "render";
  spdlog::info("{}: job {} ({}), attempt {}", options_.label, job.id(), kind, job.attempts());
  MarkAlive("job " + job.id() + ": " + kind);
  Lease lease(*this, leased);
  {
    std::lock_guard lock(mu_);
    current_ = &lease;
    if (stopping_) lease.Interrupt(Interruption::kStopping);
  }
  struct ClearCurrent {
    WorkerLoop& loop;
    ~ClearCurrent() {
      std::lock_guard lock(loop.mu_);
      loop.current_ = nullptr;
    }
  } clear_current{*this};

  lease.Log(std::string(kind) + " on " + options_.label + " (" + runner.device().gl_renderer + ")");
  std::string failure;
  // Bad input (the spec does not validate, a mesh does not parse: kInvalidArgument
  // from the work itself, not from its uploads) fails the same way on every worker:
  // no retry.
  v1::FailJobRequest::Kind fail_kind = v1::FailJobRequest::KIND_RETRYABLE;
  bool work_done = false;
  try {
    double run_ms = 0;
    const std::vector<NamedFile> files = Execute(runner, fits, leased, lease, run_ms);
    work_done = true;
    // A render runs to the end even when stopping; a cancel or lost lease drops it.
    const Interruption why = lease.interruption();
    if (why == Interruption::kCancelled || why == Interruption::kLeaseLost) throw JobInterrupted{};
    v1::CompleteJobRequest complete;
    for (const NamedFile& file : files) {
      v1::UploadArtifactRequest::Header header;
      *header.mutable_artifact() = rpc::MakeArtifactRef(file.name, file.bytes);
      header.set_job_id(job.id());
      header.set_fencing_token(lease.token());
      *complete.add_artifacts() = rpc::UploadArtifact(*stub_, header, file.bytes);
    }
    complete.set_worker_id(worker_id_);
    complete.set_job_id(job.id());
    complete.set_fencing_token(lease.token());
    complete.set_run_ms(run_ms);
    lease.Log(std::string(kind) + " done");
    for (std::string& line : lease.TakeLog()) complete.add_log_lines(std::move(line));
    grpc::ClientContext context;
    context.set_deadline(rpc::DeadlineIn(30s));
    v1::CompleteJobResponse response;
    rpc::ThrowIfFailed(stub_->CompleteJob(&context, complete, &response), "CompleteJob");
    ++completed_jobs_;
    spdlog::info("{}: job {} completed", options_.label, job.id());
    return;
  } catch (const JobInterrupted&) {
    switch (lease.interruption()) {
      case Interruption::kLeaseLost:
        spdlog::warn("{}: job {}: the lease was lost; dropping it", options_.label, job.id());
        return;
      case Interruption::kCancelled:
        failure = "cancelled on request";
        break;
      default:
        failure = "handed back: worker " + options_.label + " is stopping";
        fail_kind = v1::FailJobRequest::KIND_HANDED_BACK;
        break;
    }
  } catch (const Error& error) {
    if (error.code() == ErrorCode::kUnavailable) throw;  // the server is gone: the lease will expire there
    if (error.code() == ErrorCode::kFailedPrecondition && lease.interruption() == Interruption::kLeaseLost) return;
    failure = error.what();
    if (!work_done && error.code() == ErrorCode::kInvalidArgument) fail_kind = v1::FailJobRequest::KIND_PERMANENT;
  } catch (const std::exception& error) {
    failure = std::string("internal error: ") + error.what();
  }
  spdlog::warn("{}: job {} failed: {}", options_.label, job.id(), failure);
  lease.Log("failed: " + failure);
  v1::FailJobRequest fail;
  fail.set_worker_id(worker_id_);
  fail.set_job_id(job.id());
  fail.set_fencing_token(lease.token());
  fail.set_error(failure);
  fail.set_kind(fail_kind);
  for (std::string& line : lease.TakeLog()) fail.add_log_lines(std::move(line));
  grpc::ClientContext context;
  context.set_deadline(rpc::DeadlineIn(30s));
  v1::FailJobResponse response;
  const grpc::Status status = stub_->FailJob(&context, fail, &response);
  if (status.error_code() == grpc::StatusCode::UNAVAILABLE) rpc::ThrowIfFailed(status, "FailJob");
  if (!status.ok()) spdlog::warn("{}: FailJob {}: {}", options_.label, job.id(), status.error_message());
}

}  // namespace loom::worker
