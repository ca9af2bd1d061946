// loom cache list|show|get|rm|pin, loom server-info, loom workers

#include <cstdio>

#include "client/client_command.h"

namespace loom::client {
namespace {

void PrintFabricLine(const v1::CachedFabric& fabric) {
  std::printf("%s %10.1f KiB%s\n", fabric.fabric_key().c_str(), static_cast<double>(fabric.total_bytes()) / 1024.0,
              fabric.pinned() ? "  pinned" : "");
}

}  // namespace

std::vector<ClientCommand> AddCacheCommands(CLI::App& app, ClientFlags& flags) {
  std::vector<ClientCommand> commands;
  auto* cache = app.add_subcommand("cache", "The server's fabric cache");

  auto* list = cache->add_subcommand("list", "Cached fabrics, most recently used first");
  commands.push_back({list, [&flags] {
                        const v1::ListFabricsResponse response = flags.Connect().ListFabrics();
                        if (flags.json) {
                          PrintJson(response);
                          return 0;
                        }
                        for (const v1::CachedFabric& fabric : response.fabrics()) PrintFabricLine(fabric);
                        std::printf("%d fabric(s), %.1f MiB", response.fabrics_size(),
                                    static_cast<double>(response.total_bytes()) / (1 << 20));
                        if (response.budget_bytes() > 0) {
                          std::printf(" of %.1f MiB", static_cast<double>(response.budget_bytes()) / (1 << 20));
                        }
                        std::printf("\n");
                        return 0;
                      }});

  auto key = std::make_shared<std::string>();
  auto add = [&](const char* name, const char* help) {
    auto* command = cache->add_subcommand(name, help);
    command->add_option("key", *key, "Fabric key (or a unique prefix of at least 8 hex digits)")->required();
    return command;
  };

  commands.push_back({add("show", "A cached fabric's files and manifest"), [&flags, key] {
                        const v1::GetFabricResponse response = flags.Connect().GetFabric(*key);
                        if (flags.json) {
                          PrintJson(response);
                          return 0;
                        }
                        PrintFabricLine(response.fabric());
                        for (const v1::ArtifactRef& file : response.fabric().files()) {
                          std::printf("  %-15s %10llu bytes  %s\n", file.name().c_str(),
                                      static_cast<unsigned long long>(file.size()), file.sha256().c_str());
                        }
                        std::printf("%s\n", response.manifest_json().c_str());
                        return 0;
                      }});

  auto out = std::make_shared<std::string>();
  auto* get = add("get", "Download a cached fabric asset into a directory");
  get->add_option("--out,-o", *out, "Directory to write the asset's files (its method's images and manifest.json) into")->required();
  commands.push_back({get, [&flags, key, out] {
                        const v1::CachedFabric fabric = flags.Connect().DownloadFabric(*key, *out);
                        if (flags.json) PrintJson(fabric);
                        else std::printf("wrote %s (%d files)\n", out->c_str(), fabric.files_size());
                        return 0;
                      }});

  commands.push_back({add("rm", "Delete a cached fabric (even a pinned one)"), [&flags, key] {
                        flags.Connect().DeleteFabric(*key);
                        if (!flags.json) std::printf("deleted %s\n", key->c_str());
                        else std::printf("{}\n");
                        return 0;
                      }});

  auto unpin = std::make_shared<bool>(false);
  auto* pin = add("pin", "Keep a cached fabric from eviction");
  pin->add_flag("--unpin", *unpin, "Allow eviction again");
  commands.push_back({pin, [&flags, key, unpin] {
                        const v1::CachedFabric fabric = flags.Connect().PinFabric(*key, !*unpin);
                        if (flags.json) PrintJson(fabric);
                        else PrintFabricLine(fabric);
                        return 0;
                      }});

  auto* info = app.add_subcommand("server-info", "The server's version, health and queue depth");
  auto wait_seconds = std::make_shared<double>(0.0);
  info->add_option("--wait", *wait_seconds, "Wait up to this many seconds for the server to come up")
      ->check(CLI::Range(0.0, 600.0));
  commands.push_back({info, [&flags, wait_seconds] {
                        if (*wait_seconds > 0) {
                          flags.Connect().WaitForServer(
                              std::chrono::milliseconds(static_cast<int64_t>(*wait_seconds * 1000)));
                        }
                        const v1::ServerInfo info = flags.Connect().ServerInfo();
                        if (flags.json) {
                          PrintJson(info);
                          return 0;
                        }
                        std::printf(
                            "loom-server %s at %s: %s\n  jobs: %llu queued, %llu running\n  workers: %llu\n"
                            "  cached fabrics: %llu\n  auth: %s, tls: %s\n",
                            info.version().c_str(), flags.channel.address.c_str(), info.health().c_str(),
                            static_cast<unsigned long long>(info.queued_jobs()),
                            static_cast<unsigned long long>(info.running_jobs()),
                            static_cast<unsigned long long>(info.registered_workers()),
                            static_cast<unsigned long long>(info.cached_fabrics()),
                            info.auth_required() ? "tokens" : "none (loopback only)", info.tls() ? "on" : "off");
                        return 0;
                      }});

  auto* workers = app.add_subcommand("workers", "The workers the server knows: state, job, GL renderer, jobs done");
  commands.push_back({workers, [&flags] {
                        const v1::ListWorkersResponse list = flags.Connect().ListWorkers();
                        if (flags.json) {
                          PrintJson(list);
                          return 0;
                        }
                        for (const v1::WorkerInfo& worker : list.workers()) {
                          std::printf("%s  %-5s %-10s %u done, %u failed  %s | %s\n", worker.worker_id().c_str(),
                                      worker.state().c_str(),
                                      worker.current_job_id().empty() ? "-" : worker.current_job_id().c_str(),
                                      worker.jobs_succeeded(), worker.jobs_failed(),
                                      worker.capabilities().hostname().c_str(),
                                      worker.capabilities().gl_renderer().c_str());
                        }
                        return 0;
                      }});
  return commands;
}

}  // namespace loom::client
