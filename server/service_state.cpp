#include "server/service_state.h"

#include <spdlog/spdlog.h>

#include <iomanip>
#include <random>
#include <sstream>

#include "server/job_submission.h"

namespace loom::server {

std::string WorkerRegistry::Register(const v1::WorkerCapabilities& capabilities) {
  // Random, so that ids stay distinct across server restarts: the queue remembers
  // which worker failed which job.
  std::random_device random;
  std::ostringstream id;
  id << "w-" << std::hex << std::setfill('0') << std::setw(8) << random() << std::setw(8) << random();
  std::lock_guard lock(mu_);
  workers_[id.str()] = capabilities;
  spdlog::info("worker {} registered: {} | {}, {} cores, {:.1f} GiB ({})", id.str(), capabilities.gl_vendor(),
               capabilities.gl_renderer(), capabilities.cores(),
               static_cast<double>(capabilities.memory_bytes()) / (1 << 30), capabilities.hostname());
  return id.str();
}

size_t WorkerRegistry::size() const {
  std::lock_guard lock(mu_);
  return workers_.size();
}

ServiceState::ServiceState(JobQueue& queue, ArtifactStore& artifacts, FabricCache& cache, const Clock& clock,
                           std::string client_token, std::string worker_token, bool tls)
    : queue(queue), artifacts(artifacts), cache(cache), clock(clock), client_token(std::move(client_token)),
      worker_token(std::move(worker_token)), tls(tls) {
  queue.OnJobEnded([&artifacts](const std::string& id, v1::JobKind kind) {
    if (kind == v1::JOB_KIND_RENDER) artifacts.UnpinAll(JobPinOwner(id));
  });
}

}  // namespace loom::server
