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

void ReleaseIfEnded(ServiceState& state, const v1::Job& job) {
  const bool ended = job.state() == v1::JOB_STATE_SUCCEEDED || job.state() == v1::JOB_STATE_FAILED ||
                     job.state() == v1::JOB_STATE_CANCELLED;
  if (ended && job.kind() == v1::JOB_KIND_RENDER) state.artifacts.UnpinAll(JobPinOwner(job.id()));
}

}  // namespace loom::server
