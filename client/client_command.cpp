#include "client/client_command.h"

#include <cstdio>
#include <cstdlib>
#include <iostream>

#include "core/spec/spec_check.h"
#include "core/spec/spec_json.h"
#include "core/util/cli_main.h"
#include "core/util/progress_bar.h"
#include "rpc/auth.h"
#include "loom/v1/job.pb.h"

namespace loom::client {

JobClient& ClientFlags::Connect() {
  if (!client_) {
    if (!token_file.empty()) {
      channel.token = rpc::ReadTokenFile(token_file);
    } else if (const char* token = std::getenv("LOOM_TOKEN")) {
      channel.token = token;
    }
    client_ = std::make_unique<JobClient>(rpc::MakeChannel(channel));
  }
  return *client_;
}

void PrintJson(const google::protobuf::Message& message) { std::cout << SpecToJson(message, false) << std::endl; }

v1::Job WaitForJob(ClientFlags& flags, const std::string& job_id, const std::string& label, bool print_log) {
  ProgressBar bar(label);
  return flags.Connect().Watch(job_id, [&](const v1::JobEvent& event) {
    if (flags.json) {
      PrintJson(event);
      return;
    }
    if (print_log) {
      for (const std::string& line : event.log_lines()) std::printf("%s\n", line.c_str());
      std::fflush(stdout);
    }
    const v1::Job& job = event.job();
    const std::string state = v1::JobState_Name(job.state()).substr(std::string_view("JOB_STATE_").size());
    bar.Update(job.progress().fraction(), job.progress().stage().empty() ? state : job.progress().stage());
  });
}

int JobExitCode(const v1::Job& job) {
  if (job.state() == v1::JOB_STATE_SUCCEEDED) return 0;
  std::fprintf(stderr, "loom: job %s %s%s%s\n", job.id().c_str(),
               job.state() == v1::JOB_STATE_CANCELLED ? "was cancelled" : "failed",
               job.error().empty() ? "" : ": ", job.error().c_str());
  return kJobFailedExit;
}

std::vector<ClientCommand> AddSpecCommands(CLI::App& app, ClientFlags& flags) {
  struct Options {
    std::string kind, path;
    bool normalized = false;
  };
  auto options = std::make_shared<Options>();
  auto* spec = app.add_subcommand("spec", "Work with spec files");
  auto* check = spec->add_subcommand("check", "Check a spec file as the server would (strict parse + every limit)");
  check->add_option("kind", options->kind, "fabric, precompute, scene or animation")->required();
  check->add_option("file", options->path, "Spec file (JSON)")->required();
  check->add_flag("--normalized", options->normalized, "Print the spec with every default made explicit");
  return {{check, [&flags, options] {
             const SpecCheck result = CheckSpecFile(ParseSpecKind(options->kind), options->path);
             if (flags.json) {
               nlohmann::json out = SpecCheckJson(options->path, result);
               if (options->normalized) out["normalized"] = nlohmann::json::parse(result.normalized_json);
               std::cout << out.dump() << std::endl;
             } else {
               std::fprintf(result.issues.empty() ? stdout : stderr, "%s",
                            SpecCheckText(options->path, ParseSpecKind(options->kind), result).c_str());
               if (options->normalized) std::printf("%s\n", result.normalized_json.c_str());
             }
             return result.issues.empty() ? 0 : ExitCodeFor(ErrorCode::kInvalidArgument);
           }}};
}

}  // namespace loom::client
