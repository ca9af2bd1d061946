#pragma once
// Bearer tokens (DESIGN.md "Server, worker, client": separate tokens for clients and
// workers). A token travels as "authorization: Bearer <token>" metadata on every
// call; the server compares it in constant time.

#include <grpcpp/server_context.h>

#include <filesystem>
#include <string>
#include <string_view>

namespace loom::rpc {

inline constexpr char kAuthorizationKey[] = "authorization";

// The file's first line without surrounding whitespace. Error(kNotFound) if it
// cannot be read, Error(kInvalidArgument) if the token is empty.
std::string ReadTokenFile(const std::filesystem::path& path);

// "Bearer <token>".
std::string BearerHeader(std::string_view token);

// True when the call carries exactly `token` (compared in constant time).
bool HasBearerToken(const grpc::ServerContext& context, std::string_view token);

}  // namespace loom::rpc
