#pragma once
// loom::Error and gRPC status, both ways: the server answers an Error with the
// status of the same meaning, and the client turns a status back into the Error
// (and so the exit code, core/util/cli_main.h) it stands for.
//
//   kInvalidArgument    <-> INVALID_ARGUMENT (also OUT_OF_RANGE, DATA_LOSS received)
//   kNotFound           <-> NOT_FOUND
//   kUnavailable        <-> UNAVAILABLE (also DEADLINE_EXCEEDED, and CANCELLED by a
//                           server shutting down, received)
//   kFailedPrecondition <-> FAILED_PRECONDITION (also UNAUTHENTICATED, ABORTED,
//                           RESOURCE_EXHAUSTED, ALREADY_EXISTS received)
//   kInternal           <-> INTERNAL (and everything else)

#include <grpcpp/support/status.h>

#include <string_view>

#include "core/util/error.h"

namespace loom::rpc {

grpc::Status ToStatus(const Error& error);

// The Error a failed call stands for; `call` names it in the message
// ("SubmitJob: ..."). An unreachable server says which address was tried.
Error FromStatus(const grpc::Status& status, std::string_view call);

// "OK", "NOT_FOUND", …: gRPC's names of its status codes.
std::string_view StatusCodeName(grpc::StatusCode code);

// Throws FromStatus(status, call) unless status is OK.
void ThrowIfFailed(const grpc::Status& status, std::string_view call);

}  // namespace loom::rpc
