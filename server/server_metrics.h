#pragma once
// What loom-server tells Prometheus (docs/operations.md "Metrics"): RPC handling
// times by service, method and status; how long jobs took, by kind and ending; and,
// read from the store at each scrape, the queue by state and kind, the queue's and
// the cache's counters, the artifact store's bytes and the registered workers by GL
// renderer. Scrape() renders the text exposition format 0.0.4.
//
// Counters are this process's since it started (Prometheus adds up instances and
// handles restarts); the queue's depth is the store's, the same from every server
// on one store. Thread-safe.

#include <grpcpp/support/status.h>

#include <memory>
#include <string>
#include <string_view>

#include "loom/v1/job.pb.h"

namespace prometheus {
class Registry;
class Histogram;
template <typename T>
class Family;
}  // namespace prometheus

namespace loom::server {

struct ServiceState;

class ServerMetrics {
 public:
  ServerMetrics();
  ~ServerMetrics();
  ServerMetrics(const ServerMetrics&) = delete;
  ServerMetrics& operator=(const ServerMetrics&) = delete;

  // One RPC handled (server/call_guard.h): `service` "LoomService" or "WorkerService".
  void ObserveRpc(std::string_view service, std::string_view method, grpc::StatusCode code, double seconds);
  // A job that reached SUCCEEDED, FAILED or CANCELLED.
  void ObserveJobEnded(const v1::Job& job);

  std::string Scrape(const ServiceState& state) const;

 private:
  std::shared_ptr<prometheus::Registry> registry_;
  prometheus::Family<prometheus::Histogram>& rpc_seconds_;
  prometheus::Family<prometheus::Histogram>& job_seconds_;
  prometheus::Family<prometheus::Histogram>& job_run_seconds_;
};

}  // namespace loom::server
