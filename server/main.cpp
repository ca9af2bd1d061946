// loom-server: the job service (queue, fabric cache, artifacts; server/loom_server.h)
// with N in-process render workers. Runs until SIGINT or SIGTERM, then stops
// gracefully; a second signal exits at once.

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include <condition_variable>
#include <cstdio>
#include <mutex>

#include "core/util/cli_main.h"
#include "core/util/error.h"
#include "core/util/termination_signals.h"
#include "core/version.h"
#include "rpc/auth.h"
#include "rpc/channel.h"
#include "server/loom_server.h"
#include "server/store/store_migration.h"

namespace loom {
namespace {

// --migrate-from-sqlite: prints the rows copied by table.
int MigrateStore(const std::string& data, const std::string& store) {
  if (data.empty() || store.empty()) {
    throw Error(ErrorCode::kInvalidArgument,
                "--migrate-from-sqlite: needs --data (the SQLite store) and --store (the PostgreSQL to fill)");
  }
  for (const auto& [table, rows] : server::MigrateSqliteStore(data, store)) {
    std::printf("%-20s %lld rows\n", table.c_str(), static_cast<long long>(rows));
  }
  return 0;
}

int Main(int argc, char** argv) {
  TerminationSignals signals;  // before any thread starts
  CLI::App app{"loom-server " + std::string(kVersion) + ": Loom's job queue, fabric cache and artifact store"};
  app.set_version_flag("--version", kVersion);
  app.footer(
      "Without --client-token-file/--worker-token-file the server accepts every call and therefore\n"
      "listens on loopback addresses only. With them, clients send the client token (LOOM_TOKEN) and\n"
      "workers the worker token (loom-worker --token-file) as a bearer token on every call.");
  server::ServerOptions options;
  options.listen = rpc::kDefaultServerAddress;
  std::string data, client_token_file, worker_token_file;
  bool software = false;
  // Required, but checked after parsing (server/loom_server.cpp) so that an unknown
  // flag is reported as such rather than as a missing --data.
  app.add_option("--data", data, "Data directory: job queue, artifacts, fabric cache (created if missing; required)");
  app.add_option("--listen", options.listen, "Address to serve on (host:port; port 0 picks one)")
      ->capture_default_str();
  app.add_option("--local-workers", options.local_workers, "In-process render workers (0: remote workers only)")
      ->check(CLI::Range(0, 64))
      ->capture_default_str();
  app.add_option("--cache-bytes", options.cache_bytes,
                 "Artifact and fabric cache budget in bytes, least recently used evicted first (0: no limit)")
      ->capture_default_str();
  app.add_option("--result-retention-seconds", options.result_retention_seconds,
                 "A finished render's frames are kept from eviction this long after the job ends, budget or not "
                 "(0: they are ordinary cache entries)")
      ->capture_default_str();
  app.add_option("--max-attempts", options.max_attempts,
                 "Attempts per job before it fails (a worker that failed a job gets it again only when no other "
                 "live worker can take it; bad input fails at once; a SIGTERM hand-back uses none)")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  app.add_option("--blocklist-after", options.blocklist_after,
                 "A worker that failed a job this many times (or let its lease expire) is never given it again; "
                 "`loom jobs retry` clears the job's blocklist")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  app.add_option("--lease-seconds", options.lease_seconds,
                 "A worker's lease lasts this long after each heartbeat; then the job is requeued")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--stuck-seconds", options.stuck_seconds,
                 "A leased job whose progress has not moved for this long is requeued as stuck")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--max-concurrent-parses", options.max_concurrent_parses,
                 "Render submissions that parse their meshes at once; more wait. Each may take as much memory as "
                 "the mesh caps allow (docs/operations.md \"Limits\")")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  app.add_option("--client-token-file", client_token_file, "File holding the clients' bearer token")
      ->check(CLI::ExistingFile);
  app.add_option("--worker-token-file", worker_token_file, "File holding the workers' bearer token")
      ->check(CLI::ExistingFile);
  app.add_option("--tls-cert", options.tls_cert_file, "PEM certificate chain: serve TLS")->check(CLI::ExistingFile);
  app.add_option("--tls-key", options.tls_key_file, "PEM private key of --tls-cert")->check(CLI::ExistingFile);
  app.add_option("--http", options.http_listen,
                 "Serve the web dashboard on this address (host:port; port 0 picks one), behind the client token, "
                 "over HTTPS with --tls-cert (docs/dashboard.md)");
  app.add_option("--store", options.store,
                 "Keep the job queue and the cache index in this PostgreSQL (postgresql://USER@HOST/DB or a libpq "
                 "connection string) instead of SQLite under --data; artifact files stay under --data. Any number "
                 "of servers may share one store and one --data volume (docs/operations.md \"Several servers\")");
  app.add_option("--metrics", options.metrics_listen,
                 "Serve GET /metrics for Prometheus on this address (host:port; port 0 picks one): plain HTTP "
                 "without a token, for a cluster-internal port (docs/operations.md \"Metrics\")");
  options.web_root = LOOM_WEB_ROOT;
  app.add_option("--web-root", options.web_root, "The built dashboard's files (web/dist)")->capture_default_str();
  app.add_flag("--software", software, "Local workers use Mesa's software device (llvmpipe) even with a GPU");
  app.add_option("--gl-device", options.local_worker.gl.device_index,
                 "EGL device index for the local workers' GL context (as loom-worker --probe reports it); default: "
                 "the best device, an NVIDIA GPU first")
      ->check(CLI::Range(0, 255));
  bool migrate = false;
  app.add_flag("--migrate-from-sqlite", migrate,
               "Copy the SQLite store under --data (jobs.db, cache.db) into the --store PostgreSQL, which must be "
               "empty, then exit; stop the server first (docs/operations.md \"PostgreSQL\")");
  if (const auto exit_code = ParseCommandLine(app, argc, argv)) return *exit_code;
  if (migrate) return MigrateStore(data, options.store);

  options.data_dir = data;
  if (!client_token_file.empty()) options.client_token = rpc::ReadTokenFile(client_token_file);
  if (!worker_token_file.empty()) options.worker_token = rpc::ReadTokenFile(worker_token_file);
  options.local_worker.gl.software_only = software;

  server::LoomServer server(options);
  std::mutex mu;
  std::condition_variable signalled;
  bool stop = false;
  signals.Listen([&](int signal_number) {
    spdlog::info("signal {}: stopping", signal_number);
    std::lock_guard lock(mu);
    stop = true;
    signalled.notify_all();
  });
  std::unique_lock lock(mu);
  signalled.wait(lock, [&] { return stop; });
  server.Shutdown();
  return 0;
}

}  // namespace
}  // namespace loom

int main(int argc, char** argv) {
  return loom::RunMain("loom-server", [&] { return loom::Main(argc, argv); });
}
