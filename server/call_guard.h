#pragma once
// The frame of every RPC handler: the bearer-token check first (UNAUTHENTICATED,
// nothing else done), then the body, whose loom::Error becomes the status of the
// same meaning (rpc/status.h) and any other exception INTERNAL. Every handler of
// both services is one Guard call, so none can skip the check. Refusals are logged
// at a bounded rate (server/refusal_log.h).

#include <fmt/format.h>
#include <grpcpp/server_context.h>
#include <spdlog/spdlog.h>

#include <exception>
#include <string>
#include <string_view>

#include "core/util/error.h"
#include "rpc/auth.h"
#include "rpc/status.h"
#include "server/refusal_log.h"

namespace loom::server {

// `token` empty: the server runs without tokens (loopback only).
template <typename Body>
grpc::Status Guard(const grpc::ServerContext& context, const std::string& token, std::string_view call,
                   Body&& body) {
  if (!token.empty() && !rpc::HasBearerToken(context, token)) {
    WarnRefused(fmt::format("{} from {}: missing or wrong bearer token", call, context.peer()));
    return {grpc::StatusCode::UNAUTHENTICATED, "missing or wrong bearer token"};
  }
  try {
    body();
    return grpc::Status::OK;
  } catch (const Error& error) {
    spdlog::debug("{}: {}: {}", call, ErrorCodeName(error.code()), error.what());
    return rpc::ToStatus(error);
  } catch (const std::exception& error) {
    spdlog::error("{}: internal error: {}", call, error.what());
    return {grpc::StatusCode::INTERNAL, std::string(call) + ": internal error: " + error.what()};
  }
}

}  // namespace loom::server
