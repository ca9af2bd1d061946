#include "server/worker_service.h"

#include <algorithm>
#include <chrono>

#include "core/render/scene_render.h"
#include "core/util/error.h"
#include "server/artifact_upload.h"
#include "server/call_guard.h"
#include "server/job_service.h"
#include "server/job_submission.h"

namespace loom::server {
namespace {

using namespace std::chrono_literals;

void AppendLog(JobQueue& queue, const std::string& id, const google::protobuf::RepeatedPtrField<std::string>& lines) {
  for (const std::string& line : lines) queue.AppendLog(id, line);
}

}  // namespace

grpc::Status WorkerService::RegisterWorker(grpc::ServerContext* context, const v1::RegisterWorkerRequest* request,
                                           v1::RegisterWorkerResponse* response) {
  return Guard(*context, frame_, "RegisterWorker", [&] {
    response->set_worker_id(state_.workers.Register(request->capabilities()));
    state_.queue.WorkerSeen(response->worker_id());
    // Two heartbeats may be lost before the lease expires.
    response->set_heartbeat_interval_ms(
        static_cast<uint32_t>(std::max<int64_t>(state_.queue.options().lease_duration_ms / 3, 50)));
  });
}

bool WorkerService::ResolveFabrics(const JobLease& lease, v1::LeaseJobResponse& response) {
  for (const SceneFabric& fabric : RenderFabrics(lease.job.render())) {
    const std::optional<FabricEntry> entry = state_.cache.Get(fabric.key);
    if (!entry) {
      // Evicted (or found corrupt) after its precompute succeeded: precompute it
      // again (joined as usual) and let the render wait for it, its attempt unused.
      const v1::Job precompute = SubmitFabricPrecompute(fabric, lease.job.priority(), state_.queue);
      state_.queue.HandBack(lease.job.id(), lease.token,
                            "fabric " + fabric.key + " left the cache before the render ran", precompute.id());
      spdlog::info("job {}: fabric {} left the cache; waits for precompute {}", lease.job.id(), fabric.key,
                   precompute.id());
      return false;
    }
    v1::FabricAsset& asset = *response.add_fabrics();
    asset.set_fabric_key(fabric.key);
    *asset.mutable_files() = ToCachedFabric(*entry).files();
  }
  return true;
}

grpc::Status WorkerService::LeaseJob(grpc::ServerContext* context, const v1::LeaseJobRequest* request,
                                     v1::LeaseJobResponse* response) {
  return Guard(*context, frame_, "LeaseJob", [&] {
    if (request->worker_id().empty()) throw Error(ErrorCode::kInvalidArgument, "worker_id: is empty (RegisterWorker)");
    // A restarted server has forgotten its workers: they register again (NOT_FOUND
    // tells them to, worker/worker_loop.h).
    if (!state_.workers.Known(request->worker_id())) {
      throw Error(ErrorCode::kNotFound, "worker_id: " + request->worker_id() +
                                            " is not registered with this server (RegisterWorker first)");
    }
    const auto deadline =
        std::chrono::steady_clock::now() + std::chrono::milliseconds(std::min(request->wait_ms(), kMaxLeaseWaitMs));
    // Waits in slices so that a worker that hung up is not handed a job it will
    // never hear of.
    while (!context->IsCancelled() && !state_.draining) {
      state_.workers.Seen(request->worker_id(), "");
      const auto slice = std::min(deadline, std::chrono::steady_clock::now() + 1s);
      std::optional<JobLease> lease = state_.queue.LeaseWait(request->worker_id(), slice);
      if (lease && context->IsCancelled()) {
        // The worker hung up (stopped) while this call waited: it would never hear
        // of the lease, which would only expire and cost the job an attempt.
        state_.queue.HandBack(lease->job.id(), lease->token, "the worker hung up before the lease reached it");
        return;
      }
      if (lease && lease->job.kind() == v1::JOB_KIND_RENDER && !ResolveFabrics(*lease, *response)) {
        response->clear_fabrics();
        continue;
      }
      if (lease) {
        spdlog::info("job {}: leased by {} (attempt {})", lease->job.id(), request->worker_id(),
                     lease->job.attempts());
        state_.workers.Seen(request->worker_id(), lease->job.id());
        *response->mutable_job() = std::move(lease->job);
        response->set_fencing_token(lease->token);
        response->set_lease_deadline_ms(lease->deadline_ms);
        return;
      }
      if (std::chrono::steady_clock::now() >= deadline) return;
    }
  });
}

grpc::Status WorkerService::Heartbeat(grpc::ServerContext* context, const v1::HeartbeatRequest* request,
                                      v1::HeartbeatResponse* response) {
  return Guard(*context, frame_, "Heartbeat", [&] {
    const HeartbeatStatus status = state_.queue.Heartbeat(request->job_id(), request->fencing_token(),
                                                          request->progress().fraction(), request->progress().stage());
    switch (status) {
      case HeartbeatStatus::kOk: response->set_action(v1::HeartbeatResponse::ACTION_CONTINUE); break;
      case HeartbeatStatus::kCancelRequested: response->set_action(v1::HeartbeatResponse::ACTION_CANCEL); break;
      case HeartbeatStatus::kStaleToken: response->set_action(v1::HeartbeatResponse::ACTION_LEASE_LOST); return;
    }
    state_.workers.Seen(request->worker_id(), request->job_id());
    AppendLog(state_.queue, request->job_id(), request->log_lines());
    response->set_lease_deadline_ms(state_.clock.NowMs() + state_.queue.options().lease_duration_ms);
  });
}

grpc::Status WorkerService::UploadArtifact(grpc::ServerContext* context,
                                           grpc::ServerReader<v1::UploadArtifactRequest>* reader,
                                           v1::UploadArtifactResponse* response) {
  return Guard(*context, frame_, "UploadArtifact", [&] {
    *response->mutable_artifact() = ReceiveUpload(
        *reader, state_.artifacts, kMaxWorkerUploadBytes,
        [this](const v1::UploadArtifactRequest::Header& header) {
          state_.queue.CheckLease(header.job_id(), header.fencing_token());
        });
  });
}

grpc::Status WorkerService::DownloadArtifact(grpc::ServerContext* context,
                                             const v1::DownloadArtifactRequest* request,
                                             grpc::ServerWriter<v1::ArtifactChunk>* writer) {
  return Guard(*context, frame_, "DownloadArtifact",
               [&] { SendStoredArtifact(state_.artifacts, request->sha256(), *writer); });
}

grpc::Status WorkerService::CompleteJob(grpc::ServerContext* context, const v1::CompleteJobRequest* request,
                                        v1::CompleteJobResponse*) {
  return Guard(*context, frame_, "CompleteJob", [&] {
    const std::string& id = request->job_id();
    state_.queue.CheckLease(id, request->fencing_token());
    const v1::Job job = state_.queue.Get(id);
    std::vector<std::string> hashes;
    std::vector<FabricFile> files;
    std::string manifest_json;
    for (int i = 0; i < request->artifacts_size(); ++i) {
      const v1::ArtifactRef& artifact = request->artifacts(i);
      CheckArtifactHash(artifact.sha256(), "artifacts[" + std::to_string(i) + "].sha256");
      if (!state_.artifacts.Has(artifact.sha256())) {
        throw Error(ErrorCode::kFailedPrecondition,
                    "artifacts[" + std::to_string(i) + "]: " + artifact.sha256() + " was not uploaded");
      }
      hashes.push_back(artifact.sha256());
      files.push_back({artifact.name(), artifact.sha256()});
      if (artifact.name() == "manifest.json") manifest_json = state_.artifacts.Read(artifact.sha256());
    }
    AppendLog(state_.queue, id, request->log_lines());
    // A cancelled job's results are dropped (Complete ends it CANCELLED): its fabric
    // is not cached.
    if (job.kind() == v1::JOB_KIND_PRECOMPUTE && !job.cancel_requested()) {
      if (manifest_json.empty()) throw Error(ErrorCode::kInvalidArgument, "artifacts: no manifest.json");
      state_.cache.Put(job.fabric_key(), files, manifest_json);
    }
    // A render's frames (an animation's sequence) are kept until their client can have fetched them
    // (service_state.h), pinned before the job reads SUCCEEDED; a completion the
    // queue refuses (a lost lease) takes its pins back.
    const bool keep_results = KeepsResults(job.kind()) && !job.cancel_requested();
    if (keep_results) PinJobResults(state_, id, hashes);
    v1::Job ended;
    try {
      ended = state_.queue.Complete(id, request->fencing_token(), hashes, request->run_ms());
    } catch (...) {
      if (keep_results) state_.artifacts.UnpinAll(JobResultPinOwner(id));
      throw;
    }
    state_.workers.Ended(request->worker_id(), ended.state() == v1::JOB_STATE_SUCCEEDED);
    spdlog::info("job {}: {} by {}", id, v1::JobState_Name(ended.state()), request->worker_id());
    if (job.kind() == v1::JOB_KIND_PRECOMPUTE) state_.cache.Evict();
  });
}

grpc::Status WorkerService::FailJob(grpc::ServerContext* context, const v1::FailJobRequest* request,
                                    v1::FailJobResponse*) {
  return Guard(*context, frame_, "FailJob", [&] {
    state_.queue.CheckLease(request->job_id(), request->fencing_token());
    AppendLog(state_.queue, request->job_id(), request->log_lines());
    const Failure failure =
        request->kind() == v1::FailJobRequest::KIND_PERMANENT ? Failure::kPermanent : Failure::kRetryable;
    const v1::Job ended =
        request->kind() == v1::FailJobRequest::KIND_HANDED_BACK
            ? state_.queue.HandBack(request->job_id(), request->fencing_token(), request->error())
            : state_.queue.Fail(request->job_id(), request->fencing_token(), request->error(), failure);
    if (request->kind() == v1::FailJobRequest::KIND_HANDED_BACK) {
      state_.workers.Seen(request->worker_id(), "");
    } else {
      state_.workers.Ended(request->worker_id(), false);
    }
    spdlog::info("job {}: attempt failed on {} ({}): {}", ended.id(), request->worker_id(),
                 v1::JobState_Name(ended.state()), request->error());
  });
}

}  // namespace loom::server
