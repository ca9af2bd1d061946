#pragma once
// The frame of every RPC handler: the bearer-token check first (UNAUTHENTICATED,
// nothing else done), then the body, whose loom::Error becomes the status of the
// same meaning (rpc/status.h) and any other exception INTERNAL; the call's time and
// status go to the server's metrics. Every handler of both services is one Guard
// call, so none can skip the check. Refusals are logged at a bounded rate
// (server/refusal_log.h).

#include <fmt/format.h>
#include <grpcpp/server_context.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <exception>
#include <string>
#include <string_view>

#include "core/util/error.h"
#include "rpc/auth.h"
#include "rpc/status.h"
#include "server/refusal_log.h"
#include "server/server_metrics.h"

namespace loom::server {

// What a service's calls are checked and counted against.
struct CallFrame {
  std::string_view service;  // "LoomService", "WorkerService"
  const std::string& token;  // empty: the server runs without tokens (loopback only)
  ServerMetrics& metrics;
};

template <typename Body>
grpc::Status Guard(const grpc::ServerContext& context, const CallFrame& frame, std::string_view call, Body&& body) {
  const auto start = std::chrono::steady_clock::now();
  const auto finish = [&](grpc::Status status) {
    frame.metrics.ObserveRpc(frame.service, call, status.error_code(),
                             std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    return status;
  };
  if (!frame.token.empty() && !rpc::HasBearerToken(context, frame.token)) {
    WarnRefused(fmt::format("{} from {}: missing or wrong bearer token", call, context.peer()));
    return finish({grpc::StatusCode::UNAUTHENTICATED, "missing or wrong bearer token"});
  }
  try {
    body();
    return finish(grpc::Status::OK);
  } catch (const Error& error) {
    spdlog::debug("{}: {}: {}", call, ErrorCodeName(error.code()), error.what());
    return finish(rpc::ToStatus(error));
  } catch (const std::exception& error) {
    spdlog::error("{}: internal error: {}", call, error.what());
    return finish({grpc::StatusCode::INTERNAL, std::string(call) + ": internal error: " + error.what()});
  }
}

}  // namespace loom::server
