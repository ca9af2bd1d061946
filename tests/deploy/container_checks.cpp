#include "container_checks.h"

#include "binary_options.h"
#include "core/version.h"
#include "deploy_files.h"

namespace loom::deploy_test {
namespace {

const char kSecretsDir[] = "/run/secrets/";

}  // namespace

std::vector<std::string> EffectiveArgs(const ContainerSpec& container) {
  if (container.has_args) return container.args;
  const auto image = LoomImages().find(ParseImageReference(container.image).name);
  return image == LoomImages().end() ? std::vector<std::string>{} : image->second.cmd;
}

std::vector<std::string> SecretFilesNamed(const std::vector<std::string>& args) {
  std::vector<std::string> files;
  for (const std::string& arg : args) {
    if (arg.rfind(kSecretsDir, 0) == 0) files.push_back(arg.substr(sizeof(kSecretsDir) - 1));
  }
  return files;
}

std::vector<std::string> ContainerProblems(const ContainerSpec& container) {
  std::vector<std::string> problems;
  auto problem = [&](const std::string& text) { problems.push_back(container.where + ": " + text); };

  const ImageReference reference = ParseImageReference(container.image);
  const auto found = LoomImages().find(reference.name);
  if (found == LoomImages().end()) {
    problem("image " + container.image + " is not one deploy/docker/Dockerfile builds");
    return problems;
  }
  const DockerImage& image = found->second;
  if (reference.tag != kVersion) {
    problem("image " + container.image + " is not tagged with Loom's version " + kVersion);
  }
  if (image.entrypoint.empty() || !IsLoomBinary(image.entrypoint[0])) {
    problem("image " + image.title + " has no Loom binary as its ENTRYPOINT");
    return problems;
  }
  const std::string& binary = image.entrypoint[0];
  const std::vector<std::string> args = EffectiveArgs(container);
  for (const std::string& bad : LoomBinary(binary).Problems(args)) problem(bad);

  const int port = DefaultServerPort();
  if (binary == "loom-server") {
    const auto listen = OptionValue(args, "--listen");
    if (!listen || SplitAddress(*listen).port != port) {
      problem("loom-server --listen " + listen.value_or("(default)") + " is not on port " + std::to_string(port));
    }
    if (!OptionValue(args, "--data")) problem("loom-server has no --data");
  } else if (binary == "loom-worker") {
    const auto server = OptionValue(args, "--server");
    const HostPort address = SplitAddress(server.value_or(""));
    if (!server || !container.server_hosts.count(address.host) || address.port != port) {
      problem("loom-worker --server " + server.value_or("(default)") + " is not a server name here on port " +
              std::to_string(port));
    }
  }

  if (container.health_commands.empty()) problem("no health check");
  for (const std::vector<std::string>& command : container.health_commands) {
    if (command.empty() || !image.programs.count(command[0])) {
      problem("health check runs " + (command.empty() ? std::string("nothing") : command[0]) +
              ", which image " + image.title + " does not carry");
      continue;
    }
    if (command[0] != "loom-healthcheck") continue;
    const std::string expected_role = binary == "loom-server" ? "server" : "worker";
    if (command.size() < 2 || command[1] != expected_role) {
      problem("loom-healthcheck must check the " + expected_role);
      continue;
    }
    if (expected_role == "worker") {
      // `loom-healthcheck worker FLAGS` runs `loom-worker --probe FLAGS`: the probe
      // must ask for the device the worker itself uses.
      const std::vector<std::string> flags(command.begin() + 2, command.end());
      for (const std::string& bad : LoomBinary("loom-worker").Problems(flags)) problem("health check: " + bad);
      if (HasFlag(flags, "--software") != HasFlag(args, "--software")) {
        problem("the health check's --software differs from the worker's");
      }
    }
  }
  return problems;
}

}  // namespace loom::deploy_test
