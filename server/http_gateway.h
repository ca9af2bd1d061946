#pragma once
// The dashboard's HTTP side (issue 27; docs/dashboard.md): the built front end (web/)
// as static files, and LoomService's calls as JSON, POST /api/v1/<Method> with the
// request message as its body (proto3's JSON mapping). Each call is made on a
// channel to the same gRPC server with the caller's token, so the queue, the cache
// and the token check are the gRPC service's own: no token, no data.
//
// A caller's token comes as "Authorization: Bearer <token>" or as the HttpOnly cookie
// that POST /api/v1/login sets after checking the token with GetServerInfo (so that
// <img> requests carry it too); POST /api/v1/logout clears it. Calls must send
// Content-Type application/json, which a cross-site form cannot. GET
// /api/v1/artifacts/<sha256> streams a stored artifact (a job's frame) with its
// content type guessed from its first bytes.

#include <grpcpp/channel.h>

#include <filesystem>
#include <memory>
#include <string>

namespace httplib {
class Server;
}

namespace loom::server {

class HttpServing;

struct HttpOptions {
  std::string listen;              // host:port; port 0 picks a free one
  std::filesystem::path web_root;  // the built front end: must hold index.html
  // PEM files: serve HTTPS (both or neither).
  std::string tls_cert_file, tls_key_file;
};

class HttpGateway {
 public:
  // Binds and starts serving on its own threads. Error(kInvalidArgument) for a web
  // root without index.html or an address that is not host:port,
  // Error(kUnavailable) when the address cannot be bound.
  HttpGateway(HttpOptions options, std::shared_ptr<grpc::Channel> channel);
  ~HttpGateway();  // Stop()
  HttpGateway(const HttpGateway&) = delete;
  HttpGateway& operator=(const HttpGateway&) = delete;

  int port() const;
  // Stops taking requests and waits for those under way; idempotent.
  void Stop();

 private:
  struct Routes;
  std::unique_ptr<Routes> routes_;
  std::unique_ptr<httplib::Server> server_;
  std::unique_ptr<HttpServing> serving_;
};

}  // namespace loom::server
