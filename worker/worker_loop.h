#pragma once
// A render worker's life against a server: register with its capabilities, lease
// jobs (long poll), run each on its JobRunner while a heartbeat thread reports
// progress and log lines and learns of cancels and lost leases, upload the results
// (checksummed, fenced by the lease's token), complete or fail. Used by the
// loom-worker binary and by loom-server --local-workers: both talk WorkerService
// over a gRPC channel, so there is one worker code path.
//
// When the server cannot be reached the loop retries with exponential backoff
// (100 ms doubling to 5 s) and registers again; so it does when LeaseJob says the
// server does not know it (NOT_FOUND: a server restarted between two calls). Stop() ends it: no new lease; a
// precompute in progress stops at its next progress report and is handed back
// (FailJob KIND_HANDED_BACK: requeued without using up an attempt); a render finishes.

#include <grpcpp/channel.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/gl/egl_context.h"
#include "loom/v1/service.grpc.pb.h"
#include "worker/job_runner.h"

namespace loom::worker {

struct WorkerOptions {
  gl::ContextOptions gl = gl::DefaultContextOptions();
  // How long one LeaseJob may wait for work on the server.
  std::chrono::milliseconds lease_wait{10'000};
  // Shown in logs and registered with the server, e.g. "local-0".
  std::string label = "worker";
  // Called on the worker's thread before each job's work; what it throws fails the
  // attempt as the work's own error would (a loom::Error kInvalidArgument, bad
  // input, as a permanent failure; anything else, a damaged transfer included, as a
  // retryable one). Tests inject failures here.
  std::function<void(const v1::Job&)> before_job;
  // Called from the loop's own thread whenever it makes progress: "started" (the GL
  // context exists), "waiting for work" (before each lease), "server unreachable,
  // retrying", "job ID: precompute|render" and "job ID: STAGE" (a precompute's
  // progress stage; a render reports none). Not from the heartbeat thread, which
  // beats on while the work hangs. loom-worker --alive-file writes these to an
  // AliveFile (worker/alive_file.h).
  std::function<void(std::string_view state)> alive;
};

class WorkerLoop {
 public:
  WorkerLoop(std::shared_ptr<grpc::Channel> channel, WorkerOptions options);
  ~WorkerLoop();

  // Makes the EGL context on the calling thread (Error(kUnavailable) saying why
  // when none can be made), then leases and runs jobs until Stop(). Every job runs
  // on the calling thread.
  void Run();

  // Thread-safe; Run returns soon after (see above).
  void Stop();

  // Jobs this loop has completed (for tests and logs).
  uint64_t completed_jobs() const { return completed_jobs_; }

 private:
  class Lease;
  class FitCache;

  void Register(const gl::DeviceInfo& device);
  // A job, or nullopt when none came within lease_wait or Stop() was called.
  std::optional<v1::LeaseJobResponse> LeaseJob();
  // Runs one leased job to CompleteJob or FailJob. Throws Error(kUnavailable) only
  // when the server cannot be reached (the lease then expires there).
  void RunJob(JobRunner& runner, FitCache& fits, const v1::LeaseJobResponse& leased);
  // The job's result files, and the time spent in the work itself (in `run_ms`).
  std::vector<NamedFile> Execute(JobRunner& runner, FitCache& fits, const v1::LeaseJobResponse& leased, Lease& lease,
                                 double& run_ms);
  // Waits (interruptibly by Stop) before the next attempt to reach the server.
  void Backoff(std::chrono::milliseconds& delay);
  // Tells options_.alive, if set, that the loop made progress.
  void MarkAlive(std::string_view state) const;

  std::shared_ptr<grpc::Channel> channel_;
  std::unique_ptr<v1::WorkerService::Stub> stub_;
  WorkerOptions options_;
  std::string worker_id_;
  std::chrono::milliseconds heartbeat_interval_{1000};

  std::atomic<bool> stopping_{false};
  std::atomic<uint64_t> completed_jobs_{0};
  std::mutex mu_;
  std::condition_variable wake_;
  // Guarded by mu_, for Stop to reach: the LeaseJob call waiting, the job running.
  grpc::ClientContext* pending_lease_ = nullptr;
  Lease* current_ = nullptr;
};

}  // namespace loom::worker
