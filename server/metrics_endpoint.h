#pragma once
// GET /metrics for Prometheus (--metrics HOST:PORT): ServerMetrics::Scrape of the
// server's state in the text format 0.0.4, on an address of its own, plain HTTP and
// without a token, as Prometheus scrapes: it shows counts and times, never a job's
// contents or a token, and is meant for a cluster-internal port. Anything else is 404.

#include <memory>
#include <string>

namespace httplib {
class Server;
}

namespace loom::server {

class HttpServing;
struct ServiceState;

class MetricsEndpoint {
 public:
  // Binds and starts serving. Error(kInvalidArgument) for an address that is not
  // host:port, Error(kUnavailable) when it cannot be bound. `state` must outlive it.
  MetricsEndpoint(const std::string& listen, const ServiceState& state);
  ~MetricsEndpoint();  // Stop()
  MetricsEndpoint(const MetricsEndpoint&) = delete;
  MetricsEndpoint& operator=(const MetricsEndpoint&) = delete;

  int port() const;
  // Stops taking requests and waits for those under way; idempotent.
  void Stop();

 private:
  std::unique_ptr<httplib::Server> server_;
  std::unique_ptr<HttpServing> serving_;
};

}  // namespace loom::server
