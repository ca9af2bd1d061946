#pragma once
// LoomService (proto/loom/v1/service.proto): what the `loom` client calls, thin over
// the store. Every handler checks the client token (server/call_guard.h).

#include "loom/v1/service.grpc.pb.h"
#include "server/call_guard.h"
#include "server/service_state.h"

namespace loom::server {

// The largest mesh a client may upload (an OBJ of core/spec/limits.h's
// kMaxMeshTriangles is well under it).
inline constexpr uint64_t kMaxMeshUploadBytes = uint64_t{1} << 30;
// Hashes one FindMissingArtifacts may ask about: its reply stays far below a
// default client's 4 MiB receive limit.
inline constexpr int kMaxFindMissingHashes = 10'000;
// ListJobs stops a page before its jobs pass this many bytes (a default client
// receives at most 4 MiB); a single larger job still comes alone.
inline constexpr uint64_t kMaxListReplyBytes = uint64_t{3} << 20;
// Job ids one RetryJobs or DeleteJobs takes.
inline constexpr int kMaxJobIdsPerCall = 1000;

class JobService final : public v1::LoomService::Service {
 public:
  explicit JobService(ServiceState& state) : state_(state), frame_{"LoomService", state.client_token, state.metrics} {}

  grpc::Status SubmitJob(grpc::ServerContext* context, const v1::SubmitJobRequest* request,
                         v1::SubmitJobResponse* response) override;
  grpc::Status GetJob(grpc::ServerContext* context, const v1::GetJobRequest* request, v1::Job* response) override;
  grpc::Status ListJobs(grpc::ServerContext* context, const v1::ListJobsRequest* request,
                        v1::ListJobsResponse* response) override;
  grpc::Status WatchJob(grpc::ServerContext* context, const v1::WatchJobRequest* request,
                        grpc::ServerWriter<v1::JobEvent>* writer) override;
  grpc::Status CancelJob(grpc::ServerContext* context, const v1::CancelJobRequest* request,
                         v1::Job* response) override;
  grpc::Status SetJobPriority(grpc::ServerContext* context, const v1::SetJobPriorityRequest* request,
                              v1::Job* response) override;
  grpc::Status RetryJobs(grpc::ServerContext* context, const v1::RetryJobsRequest* request,
                         v1::RetryJobsResponse* response) override;
  grpc::Status DeleteJobs(grpc::ServerContext* context, const v1::DeleteJobsRequest* request,
                          v1::DeleteJobsResponse* response) override;
  grpc::Status GetJobLog(grpc::ServerContext* context, const v1::GetJobLogRequest* request,
                         v1::GetJobLogResponse* response) override;

  grpc::Status ListFabrics(grpc::ServerContext* context, const v1::ListFabricsRequest* request,
                           v1::ListFabricsResponse* response) override;
  grpc::Status GetFabric(grpc::ServerContext* context, const v1::GetFabricRequest* request,
                         v1::GetFabricResponse* response) override;
  grpc::Status DeleteFabric(grpc::ServerContext* context, const v1::DeleteFabricRequest* request,
                            v1::DeleteFabricResponse* response) override;
  grpc::Status PinFabric(grpc::ServerContext* context, const v1::PinFabricRequest* request,
                         v1::PinFabricResponse* response) override;

  grpc::Status FindMissingArtifacts(grpc::ServerContext* context, const v1::FindMissingArtifactsRequest* request,
                                    v1::FindMissingArtifactsResponse* response) override;
  grpc::Status UploadArtifact(grpc::ServerContext* context, grpc::ServerReader<v1::UploadArtifactRequest>* reader,
                              v1::UploadArtifactResponse* response) override;
  grpc::Status DownloadArtifact(grpc::ServerContext* context, const v1::DownloadArtifactRequest* request,
                                grpc::ServerWriter<v1::ArtifactChunk>* writer) override;

  grpc::Status GetServerInfo(grpc::ServerContext* context, const v1::GetServerInfoRequest* request,
                             v1::ServerInfo* response) override;
  grpc::Status ListWorkers(grpc::ServerContext* context, const v1::ListWorkersRequest* request,
                           v1::ListWorkersResponse* response) override;

 private:
  // A full key, or the one cached key with this prefix (at least 8 hex digits).
  std::string ResolveFabricKey(const std::string& key_or_prefix);

  ServiceState& state_;
  const CallFrame frame_;
};

// The cache entry as the API shows it.
v1::CachedFabric ToCachedFabric(const FabricEntry& entry);

// DownloadArtifact for both services: the verified bytes, streamed.
void SendStoredArtifact(ArtifactStore& artifacts, const std::string& sha256,
                        grpc::ServerWriter<v1::ArtifactChunk>& writer);

}  // namespace loom::server
