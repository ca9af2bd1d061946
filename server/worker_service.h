#pragma once
// WorkerService (proto/loom/v1/service.proto): what render workers call, thin over
// the job queue (leases, fencing tokens, heartbeats) and the artifact store. Every
// handler checks the worker token (server/call_guard.h).

#include "loom/v1/service.grpc.pb.h"
#include "server/call_guard.h"
#include "server/service_state.h"

namespace loom::server {

// The largest artifact a worker may upload (a fabric asset image or a frame).
inline constexpr uint64_t kMaxWorkerUploadBytes = uint64_t{4} << 30;
// The longest LeaseJob may wait for work.
inline constexpr uint32_t kMaxLeaseWaitMs = 60'000;

class WorkerService final : public v1::WorkerService::Service {
 public:
  explicit WorkerService(ServiceState& state)
      : state_(state), frame_{"WorkerService", state.worker_token, state.metrics} {}

  grpc::Status RegisterWorker(grpc::ServerContext* context, const v1::RegisterWorkerRequest* request,
                              v1::RegisterWorkerResponse* response) override;
  grpc::Status LeaseJob(grpc::ServerContext* context, const v1::LeaseJobRequest* request,
                        v1::LeaseJobResponse* response) override;
  grpc::Status Heartbeat(grpc::ServerContext* context, const v1::HeartbeatRequest* request,
                         v1::HeartbeatResponse* response) override;
  grpc::Status UploadArtifact(grpc::ServerContext* context, grpc::ServerReader<v1::UploadArtifactRequest>* reader,
                              v1::UploadArtifactResponse* response) override;
  grpc::Status DownloadArtifact(grpc::ServerContext* context, const v1::DownloadArtifactRequest* request,
                                grpc::ServerWriter<v1::ArtifactChunk>* writer) override;
  grpc::Status CompleteJob(grpc::ServerContext* context, const v1::CompleteJobRequest* request,
                           v1::CompleteJobResponse* response) override;
  grpc::Status FailJob(grpc::ServerContext* context, const v1::FailJobRequest* request,
                       v1::FailJobResponse* response) override;

 private:
  // The cached assets a leased render needs; false (after failing the lease) when
  // one is no longer cached.
  bool ResolveFabrics(const JobLease& lease, v1::LeaseJobResponse& response);

  ServiceState& state_;
  const CallFrame frame_;
};

}  // namespace loom::server
