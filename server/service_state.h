#pragma once
// What LoomService and WorkerService share: the store (server/store/), the tokens,
// the registered workers, and whether the server is shutting down.

#include <atomic>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "core/scene/mesh_sequence_cache.h"
#include "loom/v1/service.pb.h"
#include "server/parse_slots.h"
#include "server/server_metrics.h"
#include "server/store/artifact_store.h"
#include "server/store/fabric_cache.h"
#include "server/store/job_queue.h"

namespace loom::server {

// Workers that registered since the server started (in memory: a worker registers
// again after a restart, see worker/worker_loop.h), with what the dashboard shows of
// them: the lease each holds, when each was last heard from, the jobs each ended.
class WorkerRegistry {
 public:
  explicit WorkerRegistry(const Clock& clock) : clock_(clock) {}
  std::string Register(const v1::WorkerCapabilities& capabilities);
  // Whether `worker_id` registered with this process.
  bool Known(const std::string& worker_id) const;
  size_t size() const;
  // `worker_id` called now, holding the lease of `job_id` ("": none). Unknown ids are ignored.
  void Seen(const std::string& worker_id, const std::string& job_id);
  // `worker_id`'s lease ended: the job succeeded, or the attempt failed.
  void Ended(const std::string& worker_id, bool succeeded);
  // Most recently registered first; a worker not heard from for `live_ms` is "lost".
  std::vector<v1::WorkerInfo> List(int64_t live_ms) const;

 private:
  const Clock& clock_;
  mutable std::mutex mu_;
  std::map<std::string, v1::WorkerInfo> workers_;
};

struct ServiceState {
  // Listens to the queue's job endings: a render job's mesh pins are released
  // however the job ends, and the job's times go to the metrics.
  ServiceState(JobQueue& queue, ArtifactStore& artifacts, FabricCache& cache, const Clock& clock,
               std::string client_token, std::string worker_token, bool tls, int parse_slots = 2);

  JobQueue& queue;
  ArtifactStore& artifacts;
  FabricCache& cache;
  const Clock& clock;
  // Empty: no tokens (loopback-only mode).
  std::string client_token;
  std::string worker_token;
  bool tls;
  int64_t started_ms;
  WorkerRegistry workers;
  // A render's SubmitJob parses its meshes in one of these…
  ParseSlots parse_slots;
  // …and takes a glTF sequence's frames from here once it has read the sequence.
  MeshSequenceCache sequences;
  std::atomic<bool> draining{false};
  // Observes every RPC (call_guard.h) and every job's end; served by --metrics.
  ServerMetrics metrics;
  // --result-retention-seconds: how long a finished render's frames are kept from
  // eviction after the job ends (0: not at all, they are ordinary cache entries).
  int64_t result_retention_ms = 86'400'000;
};

// A render's frame and an animation's sequence are the job's own results, kept as
// below and removed with the job; a precompute's files are the fabric cache's.
inline bool KeepsResults(v1::JobKind kind) { return kind == v1::JOB_KIND_RENDER || kind == v1::JOB_KIND_ANIMATE; }

// Frames. A render's result artifacts are pinned as "result:<job id>" when its
// worker completes it, before the job reads SUCCEEDED, so that no eviction (a small
// --cache-bytes, a busy farm) takes a frame its client has not fetched yet; the pins
// go result_retention_ms after the job ended. A job that no longer exists releases
// its pins at once.
std::string JobResultPinOwner(const std::string& job_id);
// Pins `hashes` for job `job_id` (nothing if the retention is 0).
void PinJobResults(ServiceState& state, const std::string& job_id, const std::vector<std::string>& hashes);
// Releases the pins of results whose retention has passed; returns how many jobs'.
int ReleaseExpiredResults(ServiceState& state);

}  // namespace loom::server
