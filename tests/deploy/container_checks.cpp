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

  if (container.liveness.empty()) problem("no liveness health check");
  for (const bool liveness : {true, false}) {
    const std::vector<std::string>& command = liveness ? container.liveness : container.readiness;
    if (command.empty()) continue;
    const std::string check = liveness ? "liveness check" : "readiness check";
    if (!image.programs.count(command[0])) {
      problem(check + " runs " + command[0] + ", which image " + image.title + " does not carry");
      continue;
    }
    if (command[0] != "loom-healthcheck") continue;
    const std::string expected_role = binary == "loom-server" ? "server" : liveness ? "worker-alive" : "worker";
    if (command.size() < 2 || command[1] != expected_role) {
      problem(check + " must be loom-healthcheck " + expected_role);
      continue;
    }
    const std::vector<std::string> rest(command.begin() + 2, command.end());
    if (expected_role == "worker-alive") {
      // The file the running worker rewrites: the one its --alive-file names.
      const auto alive_file = OptionValue(args, "--alive-file");
      if (!alive_file) problem("loom-worker has no --alive-file for its liveness check to read");
      if (rest.size() != 1 || rest[0] != alive_file.value_or("")) {
        problem(check + " must read the worker's --alive-file " + alive_file.value_or("(none)"));
      }
    } else if (expected_role == "worker") {
      // `loom-healthcheck worker FLAGS` runs `loom-worker --probe FLAGS`: the probe
      // must ask for the device the worker itself uses.
      for (const std::string& bad : LoomBinary("loom-worker").Problems(rest)) problem(check + ": " + bad);
      if (HasFlag(rest, "--software") != HasFlag(args, "--software")) {
        problem("the " + check + "'s --software differs from the worker's");
      }
    }
  }
  return problems;
}

}  // namespace loom::deploy_test
