#pragma once
// Loom's one exception type. The code says what kind of failure it is so that
// every front end maps it the same way: loom-lab and loom to exit codes, the server
// to gRPC status codes.

#include <stdexcept>
#include <string>

namespace loom {

enum class ErrorCode {
  kInvalidArgument,     // bad spec, bad flag, bad file content: the caller must change the input
  kNotFound,            // a named file, job or artifact does not exist
  kUnavailable,         // a resource is missing right now (no GL context, server unreachable)
  kFailedPrecondition,  // the request is valid but the state forbids it
  kInternal,            // a bug or an unexpected failure of a library
};

const char* ErrorCodeName(ErrorCode code);

class Error : public std::runtime_error {
 public:
  Error(ErrorCode code, const std::string& message) : std::runtime_error(message), code_(code) {}
  ErrorCode code() const { return code_; }

 private:
  ErrorCode code_;
};

}  // namespace loom
