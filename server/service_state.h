#pragma once
// What LoomService and WorkerService share: the store (server/store/), the tokens,
// the registered workers, and whether the server is shutting down.

#include <atomic>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>

#include "loom/v1/service.pb.h"
#include "server/store/artifact_store.h"
#include "server/store/fabric_cache.h"
#include "server/store/job_queue.h"

namespace loom::server {

// Workers that registered since the server started (in memory: a worker registers
// again after a restart, see worker/worker_loop.h).
class WorkerRegistry {
 public:
  std::string Register(const v1::WorkerCapabilities& capabilities);
  size_t size() const;

 private:
  mutable std::mutex mu_;
  std::map<std::string, v1::WorkerCapabilities> workers_;
};

struct ServiceState {
  // Listens to the queue's job endings: a render job's mesh pins are released
  // however the job ends.
  ServiceState(JobQueue& queue, ArtifactStore& artifacts, FabricCache& cache, const Clock& clock,
               std::string client_token, std::string worker_token, bool tls);

  JobQueue& queue;
  ArtifactStore& artifacts;
  FabricCache& cache;
  const Clock& clock;
  // Empty: no tokens (loopback-only mode).
  std::string client_token;
  std::string worker_token;
  bool tls;
  WorkerRegistry workers;
  std::atomic<bool> draining{false};
};

}  // namespace loom::server
