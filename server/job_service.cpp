#include "server/job_service.h"

#include <algorithm>
#include <chrono>
#include <optional>

#include "core/util/error.h"
#include "core/version.h"
#include "loom/v1/job_state.h"
#include "rpc/artifact_transfer.h"
#include "server/artifact_upload.h"
#include "server/call_guard.h"
#include "server/job_submission.h"

namespace loom::server {
namespace {

using namespace std::chrono_literals;

constexpr size_t kMinKeyPrefix = 8;

// The job id of a request: INVALID_ARGUMENT when empty, so that a client that
// forgot it is not told the job does not exist.
const std::string& RequireJobId(const std::string& id, const char* field = "job_id") {
  if (id.empty()) throw Error(ErrorCode::kInvalidArgument, std::string(field) + ": is empty");
  return id;
}

// The job ids of RetryJobs / DeleteJobs: at least one, at most kMaxJobIdsPerCall,
// none empty.
std::vector<std::string> RequireJobIds(const google::protobuf::RepeatedPtrField<std::string>& ids) {
  if (ids.empty()) throw Error(ErrorCode::kInvalidArgument, "job_ids: is empty");
  if (ids.size() > kMaxJobIdsPerCall) {
    throw Error(ErrorCode::kInvalidArgument, "job_ids: " + std::to_string(ids.size()) + " ids exceed " +
                                                 std::to_string(kMaxJobIdsPerCall) + " per call");
  }
  std::vector<std::string> checked;
  for (int i = 0; i < ids.size(); ++i) {
    checked.push_back(RequireJobId(ids[i], ("job_ids[" + std::to_string(i) + "]").c_str()));
  }
  return checked;
}

}  // namespace

v1::CachedFabric ToCachedFabric(const FabricEntry& entry) {
  v1::CachedFabric fabric;
  fabric.set_fabric_key(entry.key);
  for (const FabricFile& file : entry.files) {
    v1::ArtifactRef& ref = *fabric.add_files();
    ref.set_name(file.name);
    ref.set_sha256(file.hash);
    ref.set_size(file.bytes);
  }
  fabric.set_total_bytes(entry.total_bytes);
  fabric.set_pinned(entry.pinned);
  fabric.set_created_ms(entry.created_ms);
  fabric.set_last_used_ms(entry.last_used_ms);
  return fabric;
}

void SendStoredArtifact(ArtifactStore& artifacts, const std::string& sha256,
                        grpc::ServerWriter<v1::ArtifactChunk>& writer) {
  CheckArtifactHash(sha256, "sha256");
  v1::ArtifactRef artifact;
  artifact.set_sha256(sha256);
  artifact.set_size(artifacts.Size(sha256));
  rpc::ArtifactSender sender(writer, artifact);
  artifacts.ReadInPieces(sha256, [&sender](std::string_view piece) { sender.Send(piece); });
  sender.Finish();
}

grpc::Status JobService::SubmitJob(grpc::ServerContext* context, const v1::SubmitJobRequest* request,
                                   v1::SubmitJobResponse* response) {
  return Guard(*context, frame_, "SubmitJob", [&] {
    if (state_.draining) throw Error(ErrorCode::kUnavailable, "the server is shutting down");
    // A render's meshes are parsed here: within the server's parse slots.
    std::optional<ParseSlots::Slot> slot;
    if (request->has_render()) slot.emplace(state_.parse_slots.Acquire([context] { return context->IsCancelled(); }));
    *response = server::SubmitJob(*request, state_.queue, state_.artifacts, state_.cache, &state_.sequences);
  });
}

grpc::Status JobService::GetJob(grpc::ServerContext* context, const v1::GetJobRequest* request, v1::Job* response) {
  return Guard(*context, frame_, "GetJob", [&] {
    *response = state_.queue.Get(RequireJobId(request->job_id()));
  });
}

grpc::Status JobService::ListJobs(grpc::ServerContext* context, const v1::ListJobsRequest* request,
                                  v1::ListJobsResponse* response) {
  return Guard(*context, frame_, "ListJobs", [&] {
    JobFilter filter;
    for (int i = 0; i < request->states_size(); ++i) {
      const int state = request->states(i);
      if (!v1::JobState_IsValid(state) || state == v1::JOB_STATE_UNSPECIFIED) {
        throw Error(ErrorCode::kInvalidArgument, "states[" + std::to_string(i) + "]: " + std::to_string(state) +
                                                     " is not a job state (JOB_STATE_QUEUED ... JOB_STATE_CANCELLED)");
      }
      filter.states.push_back(static_cast<v1::JobState>(state));
    }
    for (int i = 0; i < request->kinds_size(); ++i) {
      const int kind = request->kinds(i);
      if (!v1::JobKind_IsValid(kind) || kind == v1::JOB_KIND_UNSPECIFIED) {
        throw Error(ErrorCode::kInvalidArgument,
                    "kinds[" + std::to_string(i) + "]: " + std::to_string(kind) +
                        " is not a job kind (JOB_KIND_PRECOMPUTE, JOB_KIND_RENDER, JOB_KIND_ANIMATE)");
      }
      filter.kinds.push_back(static_cast<v1::JobKind>(kind));
    }
    // Read before the list: a change while listing makes the next poll list again.
    const std::string version = std::to_string(state_.started_ms) + "." + std::to_string(state_.queue.Version());
    response->set_version(version);
    if (!request->unless_version().empty() && request->unless_version() == version) {
      response->set_unchanged(true);
      return;
    }
    // The queue takes at most 1000 a page (the proto's cap); a larger ask gets that.
    const int page_size = static_cast<int>(std::min<uint32_t>(request->page_size(), 1000));
    JobPage page = state_.queue.List(filter, page_size, request->page_token(), kMaxListReplyBytes);
    for (v1::Job& job : page.jobs) {
      if (request->summary()) job.clear_payload();
      *response->add_jobs() = std::move(job);
    }
    response->set_next_page_token(page.next_page_token);
  });
}

grpc::Status JobService::WatchJob(grpc::ServerContext* context, const v1::WatchJobRequest* request,
                                  grpc::ServerWriter<v1::JobEvent>* writer) {
  return Guard(*context, frame_, "WatchJob", [&] {
    const std::string& id = RequireJobId(request->job_id());
    int64_t next_line = 0;
    uint64_t version = state_.queue.Version();
    while (true) {
      v1::JobEvent event;
      *event.mutable_job() = state_.queue.Get(id);
      for (std::string& line : state_.queue.Log(id, next_line, &next_line)) event.add_log_lines(std::move(line));
      if (!writer->Write(event) || IsTerminal(event.job().state())) return;
      // Wait for the next change, looking up every second for a client that left
      // or a server that is stopping.
      std::optional<uint64_t> changed;
      while (!changed) {
        if (context->IsCancelled()) return;
        if (state_.draining) throw Error(ErrorCode::kUnavailable, "the server is shutting down");
        changed = state_.queue.WaitForChange(id, version, std::chrono::steady_clock::now() + 1s);
      }
      version = *changed;
    }
  });
}

grpc::Status JobService::CancelJob(grpc::ServerContext* context, const v1::CancelJobRequest* request,
                                   v1::Job* response) {
  return Guard(*context, frame_, "CancelJob", [&] {
    *response = state_.queue.Cancel(RequireJobId(request->job_id()));
    spdlog::info("job {}: cancel requested ({})", response->id(), v1::JobState_Name(response->state()));
  });
}

grpc::Status JobService::SetJobPriority(grpc::ServerContext* context, const v1::SetJobPriorityRequest* request,
                                        v1::Job* response) {
  return Guard(*context, frame_, "SetJobPriority", [&] {
    *response = state_.queue.SetPriority(RequireJobId(request->job_id()), request->priority());
    spdlog::info("job {}: priority {}", response->id(), response->priority());
  });
}

grpc::Status JobService::RetryJobs(grpc::ServerContext* context, const v1::RetryJobsRequest* request,
                                   v1::RetryJobsResponse* response) {
  return Guard(*context, frame_, "RetryJobs", [&] {
    if (state_.draining) throw Error(ErrorCode::kUnavailable, "the server is shutting down");
    const std::vector<std::string> ids = RequireJobIds(request->job_ids());
    // A render's or an animation's meshes were released when it ended: they must still be here, and
    // are held again until it ends (server/job_submission.h).
    std::vector<std::string> pinned;
    try {
      for (const std::string& id : ids) {
        const v1::Job job = state_.queue.Get(id);
        for (const v1::MeshRef* mesh : UploadedMeshes(job)) {
          if (!state_.artifacts.Has(mesh->artifact())) {
            throw Error(ErrorCode::kFailedPrecondition, "job " + id + ": mesh artifact " + mesh->artifact() +
                                                            " is no longer on the server; submit the job again");
          }
          state_.artifacts.Pin(mesh->artifact(), JobPinOwner(id));
        }
        pinned.push_back(id);
      }
      for (v1::Job& job : state_.queue.Retry(ids)) *response->add_jobs() = std::move(job);
    } catch (...) {
      for (const std::string& id : pinned) state_.artifacts.UnpinAll(JobPinOwner(id));
      throw;
    }
    spdlog::info("{} job(s) retried", response->jobs_size());
  });
}

grpc::Status JobService::DeleteJobs(grpc::ServerContext* context, const v1::DeleteJobsRequest* request,
                                    v1::DeleteJobsResponse* response) {
  return Guard(*context, frame_, "DeleteJobs", [&] {
    uint32_t removed = 0;
    const std::vector<v1::Job> deleted = state_.queue.Delete(RequireJobIds(request->job_ids()));
    for (const v1::Job& job : deleted) {
      state_.artifacts.UnpinAll(JobPinOwner(job.id()));
      if (!KeepsResults(job.kind())) continue;  // a precompute's results are the cache's
      state_.artifacts.UnpinAll(JobResultPinOwner(job.id()));
      for (const std::string& hash : job.result_artifacts()) {
        try {
          state_.artifacts.Remove(hash);
          ++removed;
        } catch (const Error& error) {
          // Pinned by another job's result (the same frame), or gone already.
          if (error.code() != ErrorCode::kFailedPrecondition && error.code() != ErrorCode::kNotFound) throw;
        }
      }
    }
    response->set_deleted_jobs(static_cast<uint32_t>(deleted.size()));
    response->set_removed_frames(removed);
    spdlog::info("{} job(s) deleted, {} frame(s) removed", deleted.size(), removed);
  });
}

grpc::Status JobService::GetJobLog(grpc::ServerContext* context, const v1::GetJobLogRequest* request,
                                   v1::GetJobLogResponse* response) {
  return Guard(*context, frame_, "GetJobLog", [&] {
    state_.queue.Get(RequireJobId(request->job_id()));  // kNotFound for an unknown id
    for (std::string& line : state_.queue.Log(request->job_id(), 0)) response->add_lines(std::move(line));
  });
}

grpc::Status JobService::ListFabrics(grpc::ServerContext* context, const v1::ListFabricsRequest*,
                                     v1::ListFabricsResponse* response) {
  return Guard(*context, frame_, "ListFabrics", [&] {
    for (const FabricEntry& entry : state_.cache.List()) *response->add_fabrics() = ToCachedFabric(entry);
    response->set_total_bytes(state_.artifacts.TotalBytes());
    response->set_budget_bytes(state_.artifacts.options().budget_bytes);
  });
}

std::string JobService::ResolveFabricKey(const std::string& key_or_prefix) {
  if (key_or_prefix.size() < kMinKeyPrefix) {
    throw Error(ErrorCode::kInvalidArgument, "fabric_key: '" + key_or_prefix + "' is shorter than " +
                                                 std::to_string(kMinKeyPrefix) + " hex digits");
  }
  std::vector<std::string> matches;
  for (const FabricEntry& entry : state_.cache.List()) {
    if (entry.key.starts_with(key_or_prefix)) matches.push_back(entry.key);
  }
  if (matches.empty()) throw Error(ErrorCode::kNotFound, "fabric_key: no cached fabric " + key_or_prefix);
  if (matches.size() > 1) {
    throw Error(ErrorCode::kInvalidArgument, "fabric_key: prefix " + key_or_prefix + " matches " +
                                                 std::to_string(matches.size()) + " fabrics");
  }
  return matches.front();
}

grpc::Status JobService::GetFabric(grpc::ServerContext* context, const v1::GetFabricRequest* request,
                                   v1::GetFabricResponse* response) {
  return Guard(*context, frame_, "GetFabric", [&] {
    const std::string key = ResolveFabricKey(request->fabric_key());
    const std::optional<FabricEntry> entry = state_.cache.Get(key);
    if (!entry) {
      throw Error(ErrorCode::kNotFound, "fabric " + key + " is no longer cached (a file was missing or corrupt)");
    }
    *response->mutable_fabric() = ToCachedFabric(*entry);
    response->set_manifest_json(entry->manifest_json);
  });
}

grpc::Status JobService::DeleteFabric(grpc::ServerContext* context, const v1::DeleteFabricRequest* request,
                                      v1::DeleteFabricResponse*) {
  return Guard(*context, frame_, "DeleteFabric", [&] {
    const std::string key = ResolveFabricKey(request->fabric_key());
    state_.cache.Delete(key);
    spdlog::info("fabric {} deleted", key);
  });
}

grpc::Status JobService::PinFabric(grpc::ServerContext* context, const v1::PinFabricRequest* request,
                                   v1::PinFabricResponse* response) {
  return Guard(*context, frame_, "PinFabric", [&] {
    const std::string key = ResolveFabricKey(request->fabric_key());
    if (request->pinned()) state_.cache.Pin(key);
    else state_.cache.Unpin(key);
    for (const FabricEntry& entry : state_.cache.List()) {
      if (entry.key == key) *response->mutable_fabric() = ToCachedFabric(entry);
    }
  });
}

grpc::Status JobService::FindMissingArtifacts(grpc::ServerContext* context,
                                              const v1::FindMissingArtifactsRequest* request,
                                              v1::FindMissingArtifactsResponse* response) {
  return Guard(*context, frame_, "FindMissingArtifacts", [&] {
    if (request->sha256_size() > kMaxFindMissingHashes) {
      throw Error(ErrorCode::kInvalidArgument, "sha256: " + std::to_string(request->sha256_size()) +
                                                   " hashes exceed " + std::to_string(kMaxFindMissingHashes) +
                                                   " per call (ask in batches)");
    }
    std::vector<std::string> hashes;
    for (int i = 0; i < request->sha256_size(); ++i) {
      CheckArtifactHash(request->sha256(i), "sha256[" + std::to_string(i) + "]");
      hashes.push_back(request->sha256(i));
    }
    for (std::string& hash : state_.artifacts.Missing(hashes)) response->add_missing(std::move(hash));
  });
}

grpc::Status JobService::UploadArtifact(grpc::ServerContext* context,
                                        grpc::ServerReader<v1::UploadArtifactRequest>* reader,
                                        v1::UploadArtifactResponse* response) {
  return Guard(*context, frame_, "UploadArtifact", [&] {
    *response->mutable_artifact() =
        ReceiveUpload(*reader, state_.artifacts, kMaxMeshUploadBytes, [](const v1::UploadArtifactRequest::Header& h) {
          if (!h.job_id().empty() || h.fencing_token() != 0) {
            throw Error(ErrorCode::kInvalidArgument, "header.job_id: client uploads belong to no job");
          }
        });
  });
}

grpc::Status JobService::DownloadArtifact(grpc::ServerContext* context, const v1::DownloadArtifactRequest* request,
                                          grpc::ServerWriter<v1::ArtifactChunk>* writer) {
  return Guard(*context, frame_, "DownloadArtifact",
               [&] { SendStoredArtifact(state_.artifacts, request->sha256(), *writer); });
}

grpc::Status JobService::GetServerInfo(grpc::ServerContext* context, const v1::GetServerInfoRequest*,
                                       v1::ServerInfo* response) {
  return Guard(*context, frame_, "GetServerInfo", [&] {
    const QueueDepth depth = state_.queue.Depth();
    response->set_version(kVersion);
    response->set_health(state_.draining ? "draining" : "serving");
    response->set_queued_jobs(depth.Count(v1::JOB_STATE_QUEUED));
    response->set_running_jobs(depth.Count(v1::JOB_STATE_LEASED) + depth.Count(v1::JOB_STATE_RUNNING));
    response->set_registered_workers(state_.workers.size());
    response->set_cached_fabrics(state_.cache.Totals().fabrics);
    response->set_auth_required(!state_.client_token.empty());
    response->set_tls(state_.tls);
    response->set_uptime_ms(state_.clock.NowMs() - state_.started_ms);
  });
}

grpc::Status JobService::ListWorkers(grpc::ServerContext* context, const v1::ListWorkersRequest*,
                                     v1::ListWorkersResponse* response) {
  return Guard(*context, frame_, "ListWorkers", [&] {
    for (v1::WorkerInfo& info : state_.workers.List(state_.queue.options().lease_duration_ms)) {
      *response->add_workers() = std::move(info);
    }
  });
}

}  // namespace loom::server
