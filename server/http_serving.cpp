#include "server/http_serving.h"

#include <httplib.h>

#include <sys/socket.h>

#include <atomic>
#include <exception>

#include "core/util/error.h"

namespace loom::server {

HostPort ParseHostPort(const std::string& flag, const std::string& listen) {
  const size_t colon = listen.rfind(':');
  int port = -1;
  try {
    if (colon != std::string::npos) port = std::stoi(listen.substr(colon + 1));
  } catch (const std::exception&) {
  }
  if (colon == std::string::npos || colon == 0 || port < 0 || port > 65535) {
    throw Error(ErrorCode::kInvalidArgument, flag + " " + listen + ": not host:port");
  }
  std::string host = listen.substr(0, colon);
  if (host.size() > 2 && host.front() == '[' && host.back() == ']') host = host.substr(1, host.size() - 2);
  return {listen, host, port};
}

std::string ExceptionText(std::exception_ptr error) {
  try {
    std::rethrow_exception(error);
  } catch (const std::exception& e) {
    return e.what();
  } catch (...) {
    return "unknown";
  }
}

HttpServing::HttpServing(httplib::Server& server, const std::string& flag, const HostPort& address)
    : server_(server) {
  // httplib's default also sets SO_REUSEPORT, with which a second server on a port
  // in use would start and share its connections with the first.
  server.set_socket_options([](socket_t socket) {
    const int yes = 1;
    setsockopt(socket, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });
  if (address.port == 0) {
    port_ = server.bind_to_any_port(address.host);
  } else if (server.bind_to_port(address.host, address.port)) {
    port_ = address.port;
  }
  if (port_ <= 0) {
    throw Error(ErrorCode::kUnavailable,
                flag + " " + address.text + ": cannot listen (in use, or not an address here)");
  }
  // stop() only ends a server already running: wait for it to be (briefly), or to
  // have ended of itself.
  auto ended = std::make_shared<std::atomic<bool>>(false);
  thread_ = std::thread([&server, ended] {
    server.listen_after_bind();
    *ended = true;
  });
  while (!server.is_running() && !*ended) std::this_thread::yield();
}

HttpServing::~HttpServing() { Stop(); }

void HttpServing::Stop() {
  if (!thread_.joinable()) return;
  server_.stop();
  thread_.join();
}

}  // namespace loom::server
