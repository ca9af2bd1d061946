#pragma once
// loom-server assembled: the store under the data directory, both gRPC services on
// one port (TLS when a certificate is given, message-size caps), a timer that ends
// expired and stuck leases, releases frames past their retention and keeps the
// cache under its budget, and N local workers. Local workers are
// worker/worker_loop.h on an in-process channel of the same server: the same
// WorkerService calls, token included, as a remote worker's, without depending on
// the listening address (wildcard, TLS name).
//
// Shutdown order: stop taking jobs (health "draining"), stop the local workers
// (renders finish, precomputes are handed back), wake long polls, stop the
// dashboard and the metrics endpoint, the gRPC server, then the timer. Jobs still leased by remote workers stay leased in the
// queue; the next start requeues them (server/store/job_queue.h).

#include <condition_variable>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "worker/worker_loop.h"

namespace grpc {
class Server;
}

namespace loom::server {

class HttpGateway;
class MetricsEndpoint;

struct ServerOptions {
  std::filesystem::path data_dir;
  // The queue's and the cache's tables: "" SQLite under data_dir (the default), or a
  // PostgreSQL URI (postgresql://…) or libpq connection string; the artifact files
  // stay under data_dir either way. One server per store for now.
  std::string store;
  // host:port; port 0 picks a free one (tests). Without tokens only loopback
  // addresses are accepted.
  std::string listen = "127.0.0.1:7450";
  int local_workers = 1;
  uint64_t cache_bytes = 0;  // 0: no budget
  // A finished render's frames are kept from eviction this long after the job
  // ends (server/service_state.h); 0: not at all.
  double result_retention_seconds = 86'400;
  uint32_t max_attempts = 3;
  // A worker that failed a job this many times is never given it again.
  uint32_t blocklist_after = 3;
  double lease_seconds = 30;
  double stuck_seconds = 600;
  // Render submissions parsing their meshes at once (server/parse_slots.h).
  int max_concurrent_parses = 2;
  // Both or neither (Error(kInvalidArgument) otherwise).
  std::string client_token, worker_token;
  // PEM files; both or neither.
  std::string tls_cert_file, tls_key_file;
  // The dashboard (server/http_gateway.h) on host:port (port 0 picks one; the same
  // loopback rule as `listen` without tokens), HTTPS with the TLS files; "" none.
  std::string http_listen;
  std::filesystem::path web_root;  // the built dashboard (web/dist)
  // GET /metrics for Prometheus on host:port (server/metrics_endpoint.h; port 0
  // picks one), plain HTTP without a token; "" none.
  std::string metrics_listen;
  worker::WorkerOptions local_worker;
};

class LoomServer {
 public:
  // Opens the store, starts serving, the timer and the local workers.
  // Error(kInvalidArgument) for inconsistent options, Error(kUnavailable) when the
  // address cannot be bound.
  explicit LoomServer(ServerOptions options);
  ~LoomServer();  // Shutdown()
  LoomServer(const LoomServer&) = delete;
  LoomServer& operator=(const LoomServer&) = delete;

  // The bound port (the chosen one for port 0) and a loopback address to reach it.
  int port() const { return port_; }
  std::string address() const;
  // The dashboard's and the metrics endpoint's bound ports, 0 without one.
  int http_port() const;
  int metrics_port() const;

  // Graceful stop (see above); idempotent.
  void Shutdown();

 private:
  struct Store;
  void TimerLoop();

  ServerOptions options_;
  std::unique_ptr<Store> store_;
  std::unique_ptr<grpc::Server> server_;
  int port_ = 0;
  std::unique_ptr<HttpGateway> http_;
  std::unique_ptr<MetricsEndpoint> metrics_;
  std::vector<std::unique_ptr<worker::WorkerLoop>> workers_;
  std::vector<std::thread> worker_threads_;
  std::thread timer_;
  std::mutex mu_;
  std::condition_variable wake_;
  bool stopping_ = false;
};

// True for 127.0.0.0/8, ::1 and "localhost" (with any port).
bool IsLoopbackAddress(const std::string& host_port);

}  // namespace loom::server
