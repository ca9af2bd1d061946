#pragma once
// loom's subcommands (the pattern of lab/lab_command.h): each Add*Commands
// registers CLI11 subcommands and returns what to run when one is chosen.
//
// Exit codes: core/util/cli_main.h's, plus kJobFailedExit when a job the command
// waited for ended FAILED or CANCELLED.

#include <CLI/CLI.hpp>
#include <google/protobuf/message.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "client/job_client.h"
#include "rpc/channel.h"

namespace loom::client {

inline constexpr int kJobFailedExit = 6;

// Flags every subcommand shares, and the connection they describe.
struct ClientFlags {
  bool json = false;  // one JSON object (or JSON lines for streams) on stdout
  rpc::ChannelOptions channel;
  // --token-file; empty: LOOM_TOKEN, read when the first call is made.
  std::string token_file;
  JobClient& Connect();

 private:
  std::unique_ptr<JobClient> client_;
};

struct ClientCommand {
  CLI::App* command;
  std::function<int()> run;  // returns the exit code
};

std::vector<ClientCommand> AddSpecCommands(CLI::App& app, ClientFlags& flags);
std::vector<ClientCommand> AddJobCommands(CLI::App& app, ClientFlags& flags);
std::vector<ClientCommand> AddCacheCommands(CLI::App& app, ClientFlags& flags);

// Protobuf JSON (snake_case names) on one line, to stdout.
void PrintJson(const google::protobuf::Message& message);

// Follows `job_id` to its end with a progress bar on a terminal (labelled
// `label`); with `print_log` the job's log lines go to stdout as they come. With
// --json every event is a JSON line. Returns the job as it ended.
v1::Job WaitForJob(ClientFlags& flags, const std::string& job_id, const std::string& label, bool print_log);

// 0 for a SUCCEEDED job; otherwise prints why to stderr and returns kJobFailedExit.
int JobExitCode(const v1::Job& job);

}  // namespace loom::client
