#pragma once
// The checks a compose service and a Kubernetes container share: the image is one
// deploy/docker/Dockerfile builds, at this version; every argument is one its
// binary accepts; the server listens on, and workers reach it at, the server's
// default port; health checks run programs the image carries: a worker's liveness
// check reads the alive file the worker writes, its readiness check asks for the
// worker's own --software choice.

#include <set>
#include <string>
#include <vector>

namespace loom::deploy_test {

struct ContainerSpec {
  std::string where;                 // for messages: "compose.yaml services.loom-server"
  std::string image;                 // as written: "loom-server:0.1.0"
  bool has_args = false;             // false: the image's CMD applies
  std::vector<std::string> args;     // compose `command`, Kubernetes `args`
  // Health checks in exec form, program first. Liveness: compose's healthcheck, the
  // image's HEALTHCHECK, Kubernetes' livenessProbe (required). Readiness: Kubernetes'
  // readinessProbe (empty elsewhere).
  std::vector<std::string> liveness;
  std::vector<std::string> readiness;
  std::set<std::string> server_hosts;  // the names the server is reachable by here
};

std::vector<std::string> ContainerProblems(const ContainerSpec& container);

// The arguments the container's binary runs with (its own, or the image's CMD).
std::vector<std::string> EffectiveArgs(const ContainerSpec& container);

// The files under /run/secrets/ that `args` name ("loom_worker_token").
std::vector<std::string> SecretFilesNamed(const std::vector<std::string>& args);

}  // namespace loom::deploy_test
