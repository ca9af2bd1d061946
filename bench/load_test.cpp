// loom_load_test: the scale-out load test (issue 30; docs/operations.md "Several
// servers"). On a PostgreSQL of its own (tests/server/store/postgres_server.h) it
// runs, one after the other, each configuration given by --servers: that many
// loom-server processes on one fresh database and one data directory, --workers
// synthetic workers (processes of this binary: lease, upload a manifest, complete;
// no rendering) that turn to the next server when theirs stops answering, and
// --jobs precompute jobs of distinct fabrics submitted through the servers in turn
// (a retry after a dead server keeps its client_request_id), all at once or --rate a
// second. With --kill, once half
// the jobs have ended, one server and one worker are killed with SIGKILL.
//
// Checks: every job SUCCEEDED, none was completed twice (the workers log each
// completion the server accepted). Prints one JSON line per configuration: jobs/s
// from the first submission to the last completion, and the p50/p99 of each job's
// submit-to-result time as the store recorded it (submitted_ms to finished_ms).
//
//   build/bench/loom_load_test --loom-server build/server/loom-server
//       --servers 1 --servers 3 --workers 8 --jobs 10000 --kill     (one line)

#include <fcntl.h>
#include <netinet/in.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "client/job_client.h"
#include "core/util/error.h"
#include "loom/v1/service.grpc.pb.h"
#include "rpc/artifact_transfer.h"
#include "rpc/channel.h"
#include "rpc/status.h"
#include "tests/server/store/postgres_server.h"
#include "tests/server/tiny_specs.h"

extern char** environ;

namespace loom {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

// --- Processes -------------------------------------------------------------------

// A port the kernel says is free now.
int FreePort() {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address);
  socklen_t length = sizeof address;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length);
  ::close(fd);
  return ntohs(address.sin_port);
}

// Starts `arguments` with stdout and stderr to `log`; its pid.
pid_t Spawn(std::vector<std::string> arguments, const fs::path& log) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  std::vector<char*> argv;
  for (std::string& argument : arguments) argv.push_back(argument.data());
  argv.push_back(nullptr);
  pid_t pid = -1;
  const int failed = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (failed) throw Error(ErrorCode::kInternal, "cannot start " + arguments[0] + ": " + std::strerror(failed));
  return pid;
}

void Stop(pid_t pid, int signal) {
  ::kill(pid, signal);
  ::waitpid(pid, nullptr, 0);
}

rpc::ChannelOptions ChannelTo(const std::string& address) {
  rpc::ChannelOptions options;
  options.address = address;
  return options;
}

// --- The synthetic worker (a process of its own) ---------------------------------

// Leases jobs from `servers` (starting at `first`, turning to the next when one
// stops answering) and completes each with one uploaded manifest; appends each
// accepted completion's job id to `completions`. Runs until killed.
int RunWorker(const std::vector<std::string>& servers, size_t first, const fs::path& completions) {
  const int log = ::open(completions.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (log < 0) throw Error(ErrorCode::kUnavailable, "cannot open " + completions.string());
  const std::string manifest = R"({"synthetic": true})";
  size_t current = first % servers.size();
  std::unique_ptr<v1::WorkerService::Stub> stub;
  std::string worker_id;
  while (true) {
    try {
      if (!stub) stub = v1::WorkerService::NewStub(rpc::MakeChannel(ChannelTo(servers[current])));
      if (worker_id.empty()) {
        grpc::ClientContext context;
        context.set_deadline(rpc::DeadlineIn(10s));
        v1::RegisterWorkerRequest request;
        request.mutable_capabilities()->set_hostname("load-test");
        v1::RegisterWorkerResponse response;
        rpc::ThrowIfFailed(stub->RegisterWorker(&context, request, &response), "RegisterWorker");
        worker_id = response.worker_id();
      }
      v1::LeaseJobResponse lease;
      {
        grpc::ClientContext context;
        context.set_deadline(rpc::DeadlineIn(10s));
        v1::LeaseJobRequest request;
        request.set_worker_id(worker_id);
        request.set_wait_ms(1000);
        rpc::ThrowIfFailed(stub->LeaseJob(&context, request, &lease), "LeaseJob");
      }
      if (!lease.has_job()) continue;
      v1::UploadArtifactRequest::Header header;
      *header.mutable_artifact() = rpc::MakeArtifactRef("manifest.json", manifest);
      header.set_job_id(lease.job().id());
      header.set_fencing_token(lease.fencing_token());
      v1::CompleteJobRequest complete;
      complete.set_worker_id(worker_id);
      complete.set_job_id(lease.job().id());
      complete.set_fencing_token(lease.fencing_token());
      *complete.add_artifacts() = rpc::UploadArtifact(*stub, header, manifest);
      grpc::ClientContext context;
      context.set_deadline(rpc::DeadlineIn(10s));
      v1::CompleteJobResponse done;
      rpc::ThrowIfFailed(stub->CompleteJob(&context, complete, &done), "CompleteJob");
      const std::string line = lease.job().id() + "\n";
      if (::write(log, line.data(), line.size()) != static_cast<ssize_t>(line.size())) return 1;
    } catch (const Error& error) {
      if (error.code() == ErrorCode::kNotFound) {
        worker_id.clear();  // a server that does not know this worker: register again
      } else if (error.code() == ErrorCode::kUnavailable) {
        current = (current + 1) % servers.size();  // the next server (the balancer's part)
        stub.reset();
        worker_id.clear();
      } else {
        std::fprintf(stderr, "%s\n", error.what());  // a stale lease: the job went elsewhere
      }
    }
  }
}

// --- The driver --------------------------------------------------------------------

struct Config {
  fs::path loom_server;
  std::vector<int> servers;
  int workers = 8;
  int jobs = 10'000;
  int submitters = 4;
  double rate = 0;  // jobs/s submitted; 0: as fast as the servers take them
  bool kill = false;
  fs::path work;
};

// One configuration's figures.
struct Result {
  int servers = 0;
  double submit_seconds = 0;  // from the first submission to the last one's answer
  double seconds = 0;
  double jobs_per_second = 0;
  int64_t p50_ms = 0, p99_ms = 0, max_ms = 0;
  int succeeded = 0, retried = 0, twice = 0, unrecorded = 0;
  bool killed = false;
};

v1::SubmitJobRequest Job(int i) {
  v1::SubmitJobRequest request = server::PrecomputeRequest();
  request.mutable_precompute()->mutable_fabric()->mutable_knit()->set_seed(static_cast<uint64_t>(i) + 1);
  request.set_client_request_id("load-" + std::to_string(i));
  return request;
}

// Calls `call` with a client of the servers in turn from `first`, passing the
// killed one (`dead`, -1: none) and any that does not answer.
template <typename Call>
auto OnAnyServer(std::vector<client::JobClient>& clients, const std::atomic<int>& dead, size_t first, Call call) {
  for (size_t tries = 0;; ++tries) {
    const size_t s = (first + tries) % clients.size();
    if (static_cast<int>(s) == dead) continue;
    try {
      return call(clients[s]);
    } catch (const Error& error) {
      if (error.code() != ErrorCode::kUnavailable || tries > 4 * clients.size()) throw;
    }
  }
}

int64_t Percentile(std::vector<int64_t> values, double p) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  return values[static_cast<size_t>(p * static_cast<double>(values.size() - 1))];
}

Result RunConfig(const Config& config, int server_count, const server::PostgresServer& postgres) {
  const std::string database = "load_" + std::to_string(server_count);
  postgres.CreateDatabase(database);
  const fs::path dir = config.work / (std::to_string(server_count) + "-servers");
  fs::remove_all(dir);
  fs::create_directories(dir / "data");
  std::vector<std::string> addresses;
  std::vector<pid_t> servers, workers;
  for (int s = 0; s < server_count; ++s) {
    addresses.push_back("127.0.0.1:" + std::to_string(FreePort()));
    servers.push_back(Spawn({config.loom_server.string(), "--data", (dir / "data").string(), "--store",
                             postgres.ConnInfo(database), "--listen", addresses.back(), "--local-workers", "0",
                             "--lease-seconds", "3"},
                            dir / ("server-" + std::to_string(s) + ".log")));
  }
  std::vector<client::JobClient> clients;
  for (const auto& address : addresses) {
    clients.emplace_back(rpc::MakeChannel(ChannelTo(address)));
    clients.back().WaitForServer(60s);
  }
  std::string server_list;
  for (const auto& address : addresses) server_list += (server_list.empty() ? "" : ",") + address;
  for (int w = 0; w < config.workers; ++w) {
    workers.push_back(Spawn({fs::read_symlink("/proc/self/exe").string(), "--worker-of", server_list,
                             "--worker-index", std::to_string(w), "--completions",
                             (dir / ("completions-" + std::to_string(w))).string()},
                            dir / ("worker-" + std::to_string(w) + ".log")));
  }

  std::atomic<int> dead{-1};
  std::atomic<int> next{0}, submitted{0};
  const auto submit_start = std::chrono::steady_clock::now();
  std::atomic<int64_t> submit_end_ms{0};  // since submit_start, when the last submitter finished
  std::vector<std::thread> submitters;
  std::mutex mu;
  std::string submit_error;
  for (int t = 0; t < config.submitters; ++t) {
    submitters.emplace_back([&] {
      // A client of its own per thread and server.
      std::vector<client::JobClient> own;
      for (const auto& address : addresses) own.emplace_back(rpc::MakeChannel(ChannelTo(address)));
      for (int i; (i = next++) < config.jobs;) {
        // --rate: job i is due i / rate seconds after the start (a pace, not a synchronisation).
        if (config.rate > 0) {
          std::this_thread::sleep_until(submit_start + std::chrono::duration<double>(i / config.rate));
        }
        try {
          OnAnyServer(own, dead, i, [&](client::JobClient& client) { return client.Submit(Job(i)); });
          ++submitted;
        } catch (const Error& error) {
          std::lock_guard lock(mu);
          submit_error = error.what();
          return;
        }
      }
      const int64_t now_ms = std::chrono::duration_cast<std::chrono::milliseconds>(
                                 std::chrono::steady_clock::now() - submit_start).count();
      for (int64_t seen = submit_end_ms; seen < now_ms && !submit_end_ms.compare_exchange_weak(seen, now_ms);) {
      }
    });
  }
  // Ended jobs, as the store counts them: submitted so far less queued and running.
  const auto ended = [&] {
    const int so_far = submitted;
    const v1::ServerInfo info =
        OnAnyServer(clients, dead, 0, [](client::JobClient& client) { return client.ServerInfo(); });
    return so_far - static_cast<int>(info.queued_jobs() + info.running_jobs());
  };
  Result result;
  result.servers = server_count;
  while (ended() < config.jobs) {
    if (config.kill && !result.killed && ended() >= config.jobs / 2) {
      dead = 0;
      Stop(servers[0], SIGKILL);
      Stop(workers[0], SIGKILL);
      servers[0] = workers[0] = -1;
      result.killed = true;
    }
    std::this_thread::sleep_for(100ms);  // a poll, not a synchronisation: the figures come from the store
  }
  for (auto& thread : submitters) thread.join();
  if (!submit_error.empty()) throw Error(ErrorCode::kInternal, "submitting: " + submit_error);
  result.submit_seconds = static_cast<double>(submit_end_ms) / 1000.0;

  // The store's record of every job.
  std::vector<int64_t> latencies;
  int64_t first_submitted = INT64_MAX, last_finished = 0;
  std::string page;
  do {
    v1::ListJobsRequest request;
    request.set_page_size(1000);
    request.set_page_token(page);
    const v1::ListJobsResponse response =
        OnAnyServer(clients, dead, 0, [&](client::JobClient& client) { return client.List(request); });
    for (const v1::Job& job : response.jobs()) {
      result.succeeded += job.state() == v1::JOB_STATE_SUCCEEDED;
      result.retried += job.attempts() > 1;
      latencies.push_back(job.timings().finished_ms() - job.timings().submitted_ms());
      first_submitted = std::min(first_submitted, job.timings().submitted_ms());
      last_finished = std::max(last_finished, job.timings().finished_ms());
    }
    page = response.next_page_token();
  } while (!page.empty());
  std::map<std::string, int> completions;
  for (int w = 0; w < config.workers; ++w) {
    std::ifstream in(dir / ("completions-" + std::to_string(w)));
    for (std::string id; std::getline(in, id);) ++completions[id];
  }
  for (const auto& [id, count] : completions) result.twice += count > 1;
  result.unrecorded = result.succeeded - static_cast<int>(completions.size());
  result.seconds = static_cast<double>(last_finished - first_submitted) / 1000.0;
  result.jobs_per_second = static_cast<double>(result.succeeded) / result.seconds;
  result.p50_ms = Percentile(latencies, 0.50);
  result.p99_ms = Percentile(latencies, 0.99);
  result.max_ms = Percentile(latencies, 1.0);

  for (pid_t pid : workers) {
    if (pid > 0) Stop(pid, SIGKILL);
  }
  for (pid_t pid : servers) {
    if (pid > 0) Stop(pid, SIGTERM);
  }
  return result;
}

int Main(int argc, char** argv) {
  CLI::App app{"loom_load_test: several loom-servers on one PostgreSQL under synthetic load"};
  Config config;
  std::string worker_of, completions;
  size_t worker_index = 0;
  app.add_option("--loom-server", config.loom_server, "The loom-server binary");
  app.add_option("--servers", config.servers, "Servers per configuration, one configuration each time given");
  app.add_option("--workers", config.workers, "Synthetic worker processes")->check(CLI::Range(1, 256));
  app.add_option("--jobs", config.jobs, "Jobs per configuration")->check(CLI::Range(2, 1'000'000));
  app.add_option("--submitters", config.submitters, "Submitting threads")->check(CLI::Range(1, 64));
  app.add_option("--rate", config.rate, "Jobs submitted per second (0: all at once, as fast as they are taken)")
      ->check(CLI::Range(0.0, 1e6));
  app.add_flag("--kill", config.kill, "SIGKILL one server and one worker half way (with 2 servers or more)");
  app.add_option("--work", config.work, "Scratch directory (logs, data)")
      ->default_val(fs::temp_directory_path() / "loom-load-test");
  app.add_option("--worker-of", worker_of, "(internal) run as a synthetic worker of these servers");
  app.add_option("--worker-index", worker_index, "(internal)");
  app.add_option("--completions", completions, "(internal)");
  CLI11_PARSE(app, argc, argv);
  if (!worker_of.empty()) {
    std::vector<std::string> servers;
    for (size_t start = 0, end; start <= worker_of.size(); start = end + 1) {
      end = std::min(worker_of.find(',', start), worker_of.size());
      servers.push_back(worker_of.substr(start, end - start));
    }
    return RunWorker(servers, worker_index, completions);
  }
  if (config.loom_server.empty() || config.servers.empty()) {
    std::fprintf(stderr, "--loom-server and at least one --servers are required\n");
    return 2;
  }
  const server::PostgresServer postgres;
  bool all_good = true;
  for (int server_count : config.servers) {
    Config one = config;
    one.kill = config.kill && server_count > 1;
    const Result r = RunConfig(one, server_count, postgres);
    const bool good = r.succeeded == config.jobs && r.twice == 0;
    all_good = all_good && good;
    std::printf(
        "{\"servers\": %d, \"workers\": %d, \"jobs\": %d, \"rate\": %g, \"killed_server_and_worker\": %s, "
        "\"succeeded\": %d, "
        "\"completed_twice\": %d, \"completions_unrecorded\": %d, \"retried\": %d, \"submit_seconds\": %.2f, "
        "\"seconds\": %.2f, "
        "\"jobs_per_second\": %.1f, \"p50_ms\": %lld, \"p99_ms\": %lld, \"max_ms\": %lld, \"exactly_once\": %s}\n",
        r.servers, config.workers, config.jobs, config.rate, r.killed ? "true" : "false", r.succeeded, r.twice,
        r.unrecorded, r.retried, r.submit_seconds, r.seconds, r.jobs_per_second, static_cast<long long>(r.p50_ms),
        static_cast<long long>(r.p99_ms), static_cast<long long>(r.max_ms), good ? "true" : "false");
    std::fflush(stdout);
  }
  return all_good ? 0 : 1;
}

}  // namespace
}  // namespace loom

int main(int argc, char** argv) { return loom::Main(argc, argv); }
