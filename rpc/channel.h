#pragma once
// The one way loom, loom-worker and the server's local workers reach a server: a
// channel whose every call carries the bearer token, over TLS when a CA
// certificate is given, with Loom's message-size cap.

#include <grpcpp/channel.h>
#include <grpcpp/support/client_interceptor.h>

#include <chrono>
#include <memory>
#include <string>
#include <vector>

namespace loom::rpc {

// loom-server listens here by default; clients and workers connect here by default.
inline constexpr char kDefaultServerAddress[] = "127.0.0.1:7450";

// The largest message either side accepts. Artifacts travel in kChunkBytes pieces,
// specs are kilobytes, so only a malformed or hostile message comes near it.
inline constexpr int kMaxMessageBytes = 8 << 20;
inline constexpr size_t kChunkBytes = 1 << 20;

struct ChannelOptions {
  std::string address = kDefaultServerAddress;
  std::string token;        // empty: send none (a server without token files)
  std::string tls_ca_file;  // PEM roots; empty: plaintext
};

std::shared_ptr<grpc::Channel> MakeChannel(const ChannelOptions& options);

// The interceptor that puts `token` on every call (none for an empty token), for
// channels made elsewhere (the server's in-process channel for its local workers).
std::vector<std::unique_ptr<grpc::experimental::ClientInterceptorFactoryInterface>> TokenInterceptors(
    const std::string& token);

// A deadline `timeout` from now, for ClientContext::set_deadline.
std::chrono::system_clock::time_point DeadlineIn(std::chrono::milliseconds timeout);

}  // namespace loom::rpc
