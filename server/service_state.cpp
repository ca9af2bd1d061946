#include "server/service_state.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <iomanip>
#include <random>
#include <sstream>
#include <string_view>

#include "core/util/error.h"
#include "server/job_submission.h"

namespace loom::server {

std::string WorkerRegistry::Register(const v1::WorkerCapabilities& capabilities) {
  // Random, so that ids stay distinct across server restarts: the queue remembers
  // which worker failed which job.
  std::random_device random;
  std::ostringstream id;
  id << "w-" << std::hex << std::setfill('0') << std::setw(8) << random() << std::setw(8) << random();
  v1::WorkerInfo info;
  info.set_worker_id(id.str());
  *info.mutable_capabilities() = capabilities;
  info.set_registered_ms(clock_.NowMs());
  info.set_last_seen_ms(info.registered_ms());
  std::lock_guard lock(mu_);
  workers_[id.str()] = std::move(info);
  spdlog::info("worker {} registered: {} | {}, {} cores, {:.1f} GiB ({})", id.str(), capabilities.gl_vendor(),
               capabilities.gl_renderer(), capabilities.cores(),
               static_cast<double>(capabilities.memory_bytes()) / (1 << 30), capabilities.hostname());
  return id.str();
}

bool WorkerRegistry::Known(const std::string& worker_id) const {
  std::lock_guard lock(mu_);
  return workers_.contains(worker_id);
}

size_t WorkerRegistry::size() const {
  std::lock_guard lock(mu_);
  return workers_.size();
}

void WorkerRegistry::Seen(const std::string& worker_id, const std::string& job_id) {
  const int64_t now = clock_.NowMs();
  std::lock_guard lock(mu_);
  const auto found = workers_.find(worker_id);
  if (found == workers_.end()) return;
  found->second.set_last_seen_ms(now);
  found->second.set_current_job_id(job_id);
}

void WorkerRegistry::Ended(const std::string& worker_id, bool succeeded) {
  const int64_t now = clock_.NowMs();
  std::lock_guard lock(mu_);
  const auto found = workers_.find(worker_id);
  if (found == workers_.end()) return;
  v1::WorkerInfo& info = found->second;
  info.set_last_seen_ms(now);
  info.clear_current_job_id();
  if (succeeded) {
    info.set_jobs_succeeded(info.jobs_succeeded() + 1);
  } else {
    info.set_jobs_failed(info.jobs_failed() + 1);
  }
}

std::vector<v1::WorkerInfo> WorkerRegistry::List(int64_t live_ms) const {
  const int64_t now = clock_.NowMs();
  std::vector<v1::WorkerInfo> list;
  {
    std::lock_guard lock(mu_);
    for (const auto& [id, info] : workers_) list.push_back(info);
  }
  for (v1::WorkerInfo& info : list) {
    info.set_state(now - info.last_seen_ms() > live_ms ? "lost" : info.current_job_id().empty() ? "idle" : "busy");
  }
  std::sort(list.begin(), list.end(), [](const v1::WorkerInfo& a, const v1::WorkerInfo& b) {
    if (a.registered_ms() != b.registered_ms()) return a.registered_ms() > b.registered_ms();
    return a.worker_id() < b.worker_id();
  });
  return list;
}

ServiceState::ServiceState(JobQueue& queue, ArtifactStore& artifacts, FabricCache& cache, const Clock& clock,
                           std::string client_token, std::string worker_token, bool tls, int parse_slots)
    : queue(queue), artifacts(artifacts), cache(cache), clock(clock), client_token(std::move(client_token)),
      worker_token(std::move(worker_token)), tls(tls), started_ms(clock.NowMs()), workers(clock),
      parse_slots(parse_slots) {
  queue.OnJobEnded([this](const std::string& id, v1::JobKind kind) {
    if (kind == v1::JOB_KIND_RENDER || kind == v1::JOB_KIND_ANIMATE) this->artifacts.UnpinAll(JobPinOwner(id));
    try {
      metrics.ObserveJobEnded(this->queue.Get(id));
    } catch (const Error& error) {
      if (error.code() != ErrorCode::kNotFound) throw;  // deleted meanwhile: nothing to observe
    }
  });
}

namespace {
constexpr std::string_view kResultPinPrefix = "result:";
}  // namespace

std::string JobResultPinOwner(const std::string& job_id) { return std::string(kResultPinPrefix) + job_id; }

void PinJobResults(ServiceState& state, const std::string& job_id, const std::vector<std::string>& hashes) {
  if (state.result_retention_ms <= 0) return;
  for (const std::string& hash : hashes) state.artifacts.Pin(hash, JobResultPinOwner(job_id));
}

int ReleaseExpiredResults(ServiceState& state) {
  const int64_t now = state.clock.NowMs();
  int released = 0;
  for (const std::string& owner : state.artifacts.PinOwners(kResultPinPrefix)) {
    const std::string job_id = owner.substr(kResultPinPrefix.size());
    try {
      const v1::Job job = state.queue.Get(job_id);
      // Not ended yet (between the pin and the completion, or a server stopped
      // there, whose restart requeues the job): kept until it ends.
      const int64_t finished = job.timings().finished_ms();
      if (finished == 0 || now - finished < state.result_retention_ms) continue;
    } catch (const Error& error) {
      if (error.code() != ErrorCode::kNotFound) throw;
    }
    state.artifacts.UnpinAll(owner);
    ++released;
  }
  return released;
}

}  // namespace loom::server
