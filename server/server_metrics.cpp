#include "server/server_metrics.h"

#include <prometheus/counter.h>
#include <prometheus/family.h>
#include <prometheus/histogram.h>
#include <prometheus/registry.h>
#include <prometheus/text_serializer.h>

#include <algorithm>
#include <cctype>
#include <deque>
#include <map>
#include <tuple>
#include <utility>
#include <vector>

#include "core/version.h"
#include "rpc/status.h"
#include "server/service_state.h"

namespace loom::server {
namespace {

using prometheus::ClientMetric;
using prometheus::MetricFamily;
using prometheus::MetricType;

// RPCs from a cache hit's GetJob (well under a millisecond) to a long poll's wait.
const prometheus::Histogram::BucketBoundaries kRpcBuckets = {0.0005, 0.001, 0.0025, 0.005, 0.01, 0.025, 0.05,
                                                             0.1,    0.25,  0.5,    1,     2.5,  5,     10,
                                                             30,     60};
// Jobs from a cached precompute (at once) to an hour-long animation.
const prometheus::Histogram::BucketBoundaries kJobBuckets = {0.1, 0.25, 0.5, 1,   2.5, 5,    10,  30,
                                                             60,  120,  300, 600, 1800, 3600, 7200};

// JOB_KIND_RENDER -> "render", JOB_STATE_SUCCEEDED -> "succeeded".
std::string EnumLabel(const std::string& name, std::string_view prefix) {
  std::string label = name.substr(std::min(name.size(), prefix.size()));
  std::transform(label.begin(), label.end(), label.begin(), [](unsigned char c) { return std::tolower(c); });
  return label;
}
std::string KindLabel(int kind) { return EnumLabel(v1::JobKind_Name(kind), "JOB_KIND_"); }
std::string StateLabel(int state) { return EnumLabel(v1::JobState_Name(state), "JOB_STATE_"); }

// A family whose values are read now, from the store.
struct Family {
  MetricFamily family;

  Family(std::string name, std::string help, MetricType type) {
    family.name = std::move(name);
    family.help = std::move(help);
    family.type = type;
  }
  Family& Add(std::vector<ClientMetric::Label> labels, double value) {
    ClientMetric metric;
    metric.label = std::move(labels);
    (family.type == MetricType::Counter ? metric.counter.value : metric.gauge.value) = value;
    family.metric.push_back(std::move(metric));
    return *this;
  }
};

std::vector<MetricFamily> StoreFamilies(const ServiceState& state) {
  std::deque<Family> families;  // references to its elements stay valid as it grows
  const auto add = [&](std::string name, std::string help, MetricType type) -> Family& {
    return families.emplace_back(std::move(name), std::move(help), type);
  };

  const QueueDepth depth = state.queue.Depth();
  Family& jobs = add("loom_jobs", "Jobs in the store by state and kind.", MetricType::Gauge);
  Family& ready = add("loom_jobs_ready", "QUEUED jobs whose dependencies all SUCCEEDED (leasable now), by kind.",
                      MetricType::Gauge);
  for (int kind = v1::JOB_KIND_UNSPECIFIED + 1; kind < v1::JobKind_ARRAYSIZE; ++kind) {
    if (!v1::JobKind_IsValid(kind)) continue;
    for (int job_state = v1::JOB_STATE_UNSPECIFIED + 1; job_state < v1::JobState_ARRAYSIZE; ++job_state) {
      if (!v1::JobState_IsValid(job_state)) continue;
      jobs.Add({{"kind", KindLabel(kind)}, {"state", StateLabel(job_state)}},
               static_cast<double>(depth.by_state_kind[job_state][kind]));
    }
    ready.Add({{"kind", KindLabel(kind)}}, static_cast<double>(depth.ready_by_kind[kind]));
  }

  const QueueCounters counters = state.queue.Counters();
  add("loom_leases_total", "Leases given to workers.", MetricType::Counter).Add({}, counters.leases);
  add("loom_lease_expiries_total", "Leases ended without the worker: no heartbeat before the deadline, or stuck.",
      MetricType::Counter)
      .Add({{"reason", "deadline"}}, counters.lease_expiries)
      .Add({{"reason", "stuck"}}, counters.stuck_leases);
  add("loom_failed_attempts_total", "Attempts that failed: a worker's report, an expired lease, a restart.",
      MetricType::Counter)
      .Add({}, counters.failed_attempts);
  add("loom_job_retries_total", "Failed attempts whose job was queued again.", MetricType::Counter)
      .Add({}, counters.retries);

  const CacheLookups lookups = state.cache.Lookups();
  add("loom_fabric_cache_lookups_total", "Fabric cache lookups by result (broken: a file was missing or corrupt).",
      MetricType::Counter)
      .Add({{"result", "hit"}}, lookups.hits)
      .Add({{"result", "miss"}}, lookups.misses)
      .Add({{"result", "broken"}}, lookups.broken);
  const CacheTotals fabrics = state.cache.Totals();
  add("loom_fabric_cache_fabrics", "Fabrics in the cache.", MetricType::Gauge)
      .Add({}, static_cast<double>(fabrics.fabrics));
  add("loom_fabric_cache_bytes", "Bytes of the cached fabrics' files.", MetricType::Gauge)
      .Add({}, static_cast<double>(fabrics.bytes));
  add("loom_artifact_store_bytes", "Bytes in the artifact store: fabrics, meshes, frames.", MetricType::Gauge)
      .Add({}, static_cast<double>(state.artifacts.TotalBytes()));
  add("loom_artifact_store_budget_bytes", "The artifact store's byte budget (0: none).", MetricType::Gauge)
      .Add({}, static_cast<double>(state.artifacts.options().budget_bytes));

  // Workers by what renders and their state; every state shown, so a query sees 0.
  std::map<std::tuple<std::string, std::string, std::string>, int> workers;
  for (const v1::WorkerInfo& info : state.workers.List(state.queue.options().lease_duration_ms)) {
    const v1::WorkerCapabilities& caps = info.capabilities();
    for (const char* worker_state : {"busy", "idle", "lost"}) {
      workers[{caps.gl_renderer(), caps.software_gl() ? "true" : "false", worker_state}] +=
          info.state() == worker_state;
    }
  }
  Family& worker_family = add("loom_workers", "Workers registered with this server, by GL renderer and state.",
                              MetricType::Gauge);
  for (const auto& [key, count] : workers) {
    const auto& [renderer, software, worker_state] = key;
    worker_family.Add({{"renderer", renderer}, {"software_gl", software}, {"state", worker_state}}, count);
  }

  add("loom_server_start_time_seconds", "When this server started (Unix time).", MetricType::Gauge)
      .Add({}, static_cast<double>(state.started_ms) / 1000.0);
  add("loom_server_draining", "1 while this server is shutting down.", MetricType::Gauge)
      .Add({}, state.draining ? 1 : 0);
  add("loom_build_info", "The server's version (always 1).", MetricType::Gauge).Add({{"version", kVersion}}, 1);

  std::vector<MetricFamily> out;
  for (Family& family : families) out.push_back(std::move(family.family));
  return out;
}

}  // namespace

ServerMetrics::ServerMetrics()
    : registry_(std::make_shared<prometheus::Registry>()),
      rpc_seconds_(prometheus::BuildHistogram()
                       .Name("loom_rpc_duration_seconds")
                       .Help("Time from an RPC's arrival to its status, by service, method and status code "
                             "(long polls: LeaseJob and WatchJob include their wait).")
                       .Register(*registry_)),
      job_seconds_(prometheus::BuildHistogram()
                       .Name("loom_job_duration_seconds")
                       .Help("Time from a job's submission to its end, by kind and ending.")
                       .Register(*registry_)),
      job_run_seconds_(prometheus::BuildHistogram()
                           .Name("loom_job_run_seconds")
                           .Help("The worker's own time in a job that SUCCEEDED, by kind.")
                           .Register(*registry_)) {}

ServerMetrics::~ServerMetrics() = default;

void ServerMetrics::ObserveRpc(std::string_view service, std::string_view method, grpc::StatusCode code,
                               double seconds) {
  rpc_seconds_
      .Add({{"service", std::string(service)}, {"method", std::string(method)},
            {"code", std::string(rpc::StatusCodeName(code))}},
           kRpcBuckets)
      .Observe(seconds);
}

void ServerMetrics::ObserveJobEnded(const v1::Job& job) {
  const v1::JobTimings& timings = job.timings();
  if (timings.finished_ms() >= timings.submitted_ms()) {
    job_seconds_.Add({{"kind", KindLabel(job.kind())}, {"state", StateLabel(job.state())}}, kJobBuckets)
        .Observe(static_cast<double>(timings.finished_ms() - timings.submitted_ms()) / 1000.0);
  }
  if (job.state() == v1::JOB_STATE_SUCCEEDED && timings.run_ms() > 0) {
    job_run_seconds_.Add({{"kind", KindLabel(job.kind())}}, kJobBuckets).Observe(timings.run_ms() / 1000.0);
  }
}

std::string ServerMetrics::Scrape(const ServiceState& state) const {
  std::vector<MetricFamily> families = registry_->Collect();
  for (MetricFamily& family : StoreFamilies(state)) families.push_back(std::move(family));
  return prometheus::TextSerializer().Serialize(families);
}

}  // namespace loom::server
