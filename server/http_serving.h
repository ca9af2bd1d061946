#pragma once
// An httplib server bound to host:port and serving on its own thread until stopped:
// what the dashboard (http_gateway.h) and the metrics endpoint (metrics_endpoint.h)
// share.

#include <exception>
#include <memory>
#include <string>
#include <thread>

namespace httplib {
class Server;
}

namespace loom::server {

struct HostPort {
  std::string text;  // as given
  std::string host;  // without the brackets of an IPv6 literal
  int port = 0;
};

// "host:port" or "[v6]:port", port in [0, 65535]; Error(kInvalidArgument) naming
// `flag` otherwise.
HostPort ParseHostPort(const std::string& flag, const std::string& listen);

// What an exception a handler threw says ("unknown" for one that is no std::exception),
// for httplib's exception handler.
std::string ExceptionText(std::exception_ptr error);

class HttpServing {
 public:
  // Binds `server` (port 0 picks a free one) and starts serving. Error(kUnavailable)
  // naming `flag` when the address cannot be bound. `server` must outlive this.
  HttpServing(httplib::Server& server, const std::string& flag, const HostPort& address);
  ~HttpServing();  // Stop()
  HttpServing(const HttpServing&) = delete;
  HttpServing& operator=(const HttpServing&) = delete;

  int port() const { return port_; }
  // Stops taking requests and waits for those under way; idempotent.
  void Stop();

 private:
  httplib::Server& server_;
  std::thread thread_;
  int port_ = 0;
};

}  // namespace loom::server
