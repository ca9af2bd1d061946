#include "server/loom_server.h"

#include <grpcpp/security/server_credentials.h>
#include <grpcpp/server.h>
#include <grpcpp/server_builder.h>
#include <spdlog/spdlog.h>

#include <chrono>

#include "core/util/error.h"
#include "core/util/file_io.h"
#include "rpc/channel.h"
#include "server/http_gateway.h"
#include "server/http_serving.h"
#include "server/job_service.h"
#include "server/metrics_endpoint.h"
#include "server/refusal_log.h"
#include "server/store/pg_db.h"
#include "server/store/sqlite_db.h"
#include "server/worker_service.h"

namespace loom::server {
namespace {

using namespace std::chrono_literals;

void CheckOptions(const ServerOptions& options) {
  if (options.data_dir.empty()) throw Error(ErrorCode::kInvalidArgument, "--data: a data directory is required");
  if (options.client_token.empty() != options.worker_token.empty()) {
    throw Error(ErrorCode::kInvalidArgument, "--client-token-file and --worker-token-file go together");
  }
  if (options.client_token.empty() && !IsLoopbackAddress(options.listen)) {
    throw Error(ErrorCode::kInvalidArgument, "--listen " + options.listen +
                                                 ": without token files the server listens on loopback only");
  }
  if (!options.http_listen.empty() && options.client_token.empty() && !IsLoopbackAddress(options.http_listen)) {
    throw Error(ErrorCode::kInvalidArgument, "--http " + options.http_listen +
                                                 ": without token files the server listens on loopback only");
  }
  if (!options.http_listen.empty()) ParseHostPort("--http", options.http_listen);
  if (!options.metrics_listen.empty()) ParseHostPort("--metrics", options.metrics_listen);
  if (options.tls_cert_file.empty() != options.tls_key_file.empty()) {
    throw Error(ErrorCode::kInvalidArgument, "--tls-cert and --tls-key go together");
  }
  if (options.local_workers < 0) throw Error(ErrorCode::kInvalidArgument, "--local-workers: must be >= 0");
  if (!(options.result_retention_seconds >= 0 && options.result_retention_seconds <= 365.0 * 86'400)) {
    throw Error(ErrorCode::kInvalidArgument, "--result-retention-seconds: must be in [0, 31536000] (a year)");
  }
  if (options.max_concurrent_parses < 1 || options.max_concurrent_parses > 64) {
    throw Error(ErrorCode::kInvalidArgument, "--max-concurrent-parses: must be in [1, 64]");
  }
  if (options.lease_seconds <= 0 || options.stuck_seconds <= 0) {
    throw Error(ErrorCode::kInvalidArgument, "--lease-seconds and --stuck-seconds: must be > 0");
  }
}

std::shared_ptr<grpc::ServerCredentials> Credentials(const ServerOptions& options) {
  if (options.tls_cert_file.empty()) return grpc::InsecureServerCredentials();
  grpc::SslServerCredentialsOptions ssl;
  ssl.pem_key_cert_pairs.push_back({ReadFile(options.tls_key_file), ReadFile(options.tls_cert_file)});
  return grpc::SslServerCredentials(ssl);
}

}  // namespace

bool IsLoopbackAddress(const std::string& host_port) {
  std::string host = host_port.substr(0, host_port.rfind(':'));
  if (host.starts_with("ipv4:")) host = host.substr(5);
  if (host.starts_with("ipv6:")) host = host.substr(5);
  return host.starts_with("127.") || host == "[::1]" || host == "localhost";
}

namespace {

// One of the store's databases: a SQLite file under --data, or a connection to
// the --store PostgreSQL (which any number of servers may share).
std::unique_ptr<SqlDb> OpenDatabase(const ServerOptions& options, const char* sqlite_file) {
  if (options.store.empty()) return std::make_unique<SqliteDb>(options.data_dir / sqlite_file);
  try {
    return std::make_unique<PgDb>(options.store);
  } catch (const Error& error) {
    throw Error(error.code(), std::string("--store: ") + error.what());
  }
}

}  // namespace

struct LoomServer::Store {
  SystemClock clock;
  ArtifactStore artifacts;
  FabricCache cache;
  JobQueue queue;
  ServiceState state;
  JobService job_service;
  WorkerService worker_service;

  explicit Store(const ServerOptions& options)
      : artifacts(options.data_dir, OpenDatabase(options, "cache.db"),
                  ArtifactStoreOptions{.budget_bytes = options.cache_bytes}),
        cache(artifacts, clock),
        queue(OpenDatabase(options, "jobs.db"), clock,
              JobQueueOptions{.lease_duration_ms = static_cast<int64_t>(options.lease_seconds * 1000),
                              .stuck_after_ms = static_cast<int64_t>(options.stuck_seconds * 1000),
                              .default_max_attempts = options.max_attempts,
                              .blocklist_after = options.blocklist_after}),
        state(queue, artifacts, cache, clock, options.client_token, options.worker_token,
              !options.tls_cert_file.empty(), options.max_concurrent_parses),
        job_service(state),
        worker_service(state) {}
};

LoomServer::LoomServer(ServerOptions options) : options_(std::move(options)) {
  RouteProtobufLogs();
  CheckOptions(options_);
  std::filesystem::create_directories(options_.data_dir);
  store_ = std::make_unique<Store>(options_);
  store_->state.result_retention_ms = static_cast<int64_t>(options_.result_retention_seconds * 1000);

  grpc::ServerBuilder builder;
  // gRPC sets SO_REUSEPORT by default: a second server on a port in use would
  // then start and silently share its connections with the first.
  builder.AddChannelArgument(GRPC_ARG_ALLOW_REUSEPORT, 0);
  builder.AddListeningPort(options_.listen, Credentials(options_), &port_);
  builder.RegisterService(&store_->job_service);
  builder.RegisterService(&store_->worker_service);
  builder.SetMaxReceiveMessageSize(rpc::kMaxMessageBytes);
  builder.SetMaxSendMessageSize(rpc::kMaxMessageBytes);
  server_ = builder.BuildAndStart();
  if (!server_ || port_ == 0) {
    throw Error(ErrorCode::kUnavailable, "cannot listen on " + options_.listen + " (in use, or not an address here)");
  }
  spdlog::info("loom-server listening on {} (port {}), data in {}, {}{}", options_.listen, port_,
               options_.data_dir.string(), options_.client_token.empty() ? "no tokens (loopback only)" : "tokens",
               options_.tls_cert_file.empty() ? "" : ", TLS");

  grpc::ChannelArguments arguments;
  arguments.SetMaxReceiveMessageSize(rpc::kMaxMessageBytes);
  arguments.SetMaxSendMessageSize(rpc::kMaxMessageBytes);
  if (!options_.http_listen.empty()) {
    http_ = std::make_unique<HttpGateway>(
        HttpOptions{.listen = options_.http_listen,
                    .web_root = options_.web_root,
                    .tls_cert_file = options_.tls_cert_file,
                    .tls_key_file = options_.tls_key_file},
        server_->experimental().InProcessChannelWithInterceptors(arguments, rpc::TokenInterceptors("")));
  }

  if (!options_.metrics_listen.empty()) {
    metrics_ = std::make_unique<MetricsEndpoint>(options_.metrics_listen, store_->state);
  }

  timer_ = std::thread([this] { TimerLoop(); });
  for (int i = 0; i < options_.local_workers; ++i) {
    worker::WorkerOptions worker_options = options_.local_worker;
    worker_options.label = "local-" + std::to_string(i);
    auto channel =
        server_->experimental().InProcessChannelWithInterceptors(arguments, rpc::TokenInterceptors(options_.worker_token));
    workers_.push_back(std::make_unique<worker::WorkerLoop>(std::move(channel), worker_options));
    worker_threads_.emplace_back([worker = workers_.back().get(), label = worker_options.label] {
      try {
        worker->Run();
      } catch (const std::exception& error) {
        spdlog::error("{}: {}; the server goes on without this worker", label, error.what());
      }
    });
  }
}

LoomServer::~LoomServer() { Shutdown(); }

std::string LoomServer::address() const { return "127.0.0.1:" + std::to_string(port_); }

int LoomServer::http_port() const { return http_ ? http_->port() : 0; }

int LoomServer::metrics_port() const { return metrics_ ? metrics_->port() : 0; }

void LoomServer::TimerLoop() {
  // Result retention is kept to the minute: each pass reads every pinned job.
  constexpr int kTicksPerRetentionPass = 60;
  std::unique_lock lock(mu_);
  for (int tick = 1; !wake_.wait_for(lock, 1s, [this] { return stopping_; }); ++tick) {
    lock.unlock();
    try {
      if (const int ended = store_->queue.RequeueExpired()) spdlog::warn("{} expired or stuck lease(s) ended", ended);
      if (tick % kTicksPerRetentionPass == 0) {
        if (const int released = ReleaseExpiredResults(store_->state)) {
          spdlog::info("{} finished job(s)' frames past their retention, now evictable", released);
        }
      }
      for (const std::string& key : store_->cache.Evict()) spdlog::info("fabric {} evicted (cache budget)", key);
    } catch (const std::exception& error) {
      spdlog::error("lease timer: {}", error.what());
    }
    lock.lock();
  }
}

void LoomServer::Shutdown() {
  {
    std::lock_guard lock(mu_);
    if (stopping_ || !store_) return;
    stopping_ = true;
  }
  spdlog::info("loom-server: shutting down");
  store_->state.draining = true;
  for (const auto& worker : workers_) worker->Stop();
  for (std::thread& thread : worker_threads_) thread.join();
  store_->queue.Shutdown();
  if (http_) http_->Stop();
  if (metrics_) metrics_->Stop();
  server_->Shutdown(std::chrono::system_clock::now() + 5s);
  wake_.notify_all();
  timer_.join();
  spdlog::info("loom-server: stopped");
}

}  // namespace loom::server
