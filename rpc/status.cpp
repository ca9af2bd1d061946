#include "rpc/status.h"

#include <string>

namespace loom::rpc {

grpc::Status ToStatus(const Error& error) {
  switch (error.code()) {
    case ErrorCode::kInvalidArgument: return {grpc::StatusCode::INVALID_ARGUMENT, error.what()};
    case ErrorCode::kNotFound: return {grpc::StatusCode::NOT_FOUND, error.what()};
    case ErrorCode::kUnavailable: return {grpc::StatusCode::UNAVAILABLE, error.what()};
    case ErrorCode::kFailedPrecondition: return {grpc::StatusCode::FAILED_PRECONDITION, error.what()};
    case ErrorCode::kInternal: return {grpc::StatusCode::INTERNAL, error.what()};
  }
  return {grpc::StatusCode::INTERNAL, error.what()};
}

Error FromStatus(const grpc::Status& status, std::string_view call) {
  const std::string message = std::string(call) + ": " + status.error_message();
  switch (status.error_code()) {
    case grpc::StatusCode::INVALID_ARGUMENT:
    case grpc::StatusCode::OUT_OF_RANGE:
    case grpc::StatusCode::DATA_LOSS: return Error(ErrorCode::kInvalidArgument, message);
    case grpc::StatusCode::NOT_FOUND: return Error(ErrorCode::kNotFound, message);
    case grpc::StatusCode::UNAVAILABLE:
    case grpc::StatusCode::DEADLINE_EXCEEDED:
    case grpc::StatusCode::CANCELLED:  // the server cancelled the call: it is shutting down
      return Error(ErrorCode::kUnavailable, message + " (is loom-server running and reachable?)");
    case grpc::StatusCode::UNAUTHENTICATED:
      return Error(ErrorCode::kFailedPrecondition, message + " (check the token: LOOM_TOKEN or --token-file)");
    case grpc::StatusCode::FAILED_PRECONDITION:
    case grpc::StatusCode::ABORTED:
    case grpc::StatusCode::RESOURCE_EXHAUSTED:
    case grpc::StatusCode::ALREADY_EXISTS:
    case grpc::StatusCode::PERMISSION_DENIED: return Error(ErrorCode::kFailedPrecondition, message);
    default: return Error(ErrorCode::kInternal, message);
  }
}

void ThrowIfFailed(const grpc::Status& status, std::string_view call) {
  if (!status.ok()) throw FromStatus(status, call);
}

std::string_view StatusCodeName(grpc::StatusCode code) {
  switch (code) {
    case grpc::StatusCode::OK: return "OK";
    case grpc::StatusCode::CANCELLED: return "CANCELLED";
    case grpc::StatusCode::UNKNOWN: return "UNKNOWN";
    case grpc::StatusCode::INVALID_ARGUMENT: return "INVALID_ARGUMENT";
    case grpc::StatusCode::DEADLINE_EXCEEDED: return "DEADLINE_EXCEEDED";
    case grpc::StatusCode::NOT_FOUND: return "NOT_FOUND";
    case grpc::StatusCode::ALREADY_EXISTS: return "ALREADY_EXISTS";
    case grpc::StatusCode::PERMISSION_DENIED: return "PERMISSION_DENIED";
    case grpc::StatusCode::UNAUTHENTICATED: return "UNAUTHENTICATED";
    case grpc::StatusCode::RESOURCE_EXHAUSTED: return "RESOURCE_EXHAUSTED";
    case grpc::StatusCode::FAILED_PRECONDITION: return "FAILED_PRECONDITION";
    case grpc::StatusCode::ABORTED: return "ABORTED";
    case grpc::StatusCode::OUT_OF_RANGE: return "OUT_OF_RANGE";
    case grpc::StatusCode::UNIMPLEMENTED: return "UNIMPLEMENTED";
    case grpc::StatusCode::INTERNAL: return "INTERNAL";
    case grpc::StatusCode::UNAVAILABLE: return "UNAVAILABLE";
    case grpc::StatusCode::DATA_LOSS: return "DATA_LOSS";
    default: return "UNKNOWN";
  }
}

}  // namespace loom::rpc
