#include "server/store/pg_listener.h"

#include <libpq-fe.h>
#include <poll.h>
#include <spdlog/spdlog.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>

#include "core/util/error.h"
#include "server/store/pg_db.h"

namespace loom::server {

PgListener::PgListener(std::string conninfo, std::string channel,
                       std::function<void(const std::string& payload)> on_notify)
    : conninfo_(std::move(conninfo)), channel_(std::move(channel)), on_notify_(std::move(on_notify)) {
  stop_fd_ = ::eventfd(0, EFD_CLOEXEC);
  if (stop_fd_ < 0) throw Error(ErrorCode::kInternal, "PostgreSQL listener: cannot create an eventfd");
  try {
    Connect();
  } catch (...) {
    ::close(stop_fd_);
    throw;
  }
  thread_ = std::thread([this] { Run(); });
}

PgListener::~PgListener() {
  const uint64_t one = 1;
  [[maybe_unused]] const auto written = ::write(stop_fd_, &one, sizeof one);
  thread_.join();
  if (conn_) PQfinish(conn_);
  ::close(stop_fd_);
}

void PgListener::Connect() {
  if (conn_) PQfinish(conn_);
  conn_ = PQconnectdb(conninfo_.c_str());
  std::string failure;
  if (!conn_) {
    failure = "out of memory";
  } else if (PQstatus(conn_) != CONNECTION_OK) {
    failure = PgMessageLine(PQerrorMessage(conn_));
  } else {
    char* name = PQescapeIdentifier(conn_, channel_.data(), channel_.size());
    PGresult* result = PQexec(conn_, (std::string("LISTEN ") + (name ? name : "")).c_str());
    if (name) PQfreemem(name);
    if (PQresultStatus(result) != PGRES_COMMAND_OK) failure = PgMessageLine(PQerrorMessage(conn_));
    PQclear(result);
  }
  if (failure.empty()) return;
  if (conn_) PQfinish(conn_);
  conn_ = nullptr;
  throw Error(ErrorCode::kUnavailable, "PostgreSQL: cannot listen on " + channel_ + ": " + failure);
}

bool PgListener::Wait(int timeout_ms, bool on_socket) {
  pollfd fds[2] = {{stop_fd_, POLLIN, 0}, {on_socket ? PQsocket(conn_) : -1, POLLIN, 0}};
  while (::poll(fds, 2, timeout_ms) < 0) {
    if (errno != EINTR) throw Error(ErrorCode::kInternal, "PostgreSQL listener: poll failed");
  }
  return fds[0].revents == 0;
}

void PgListener::Run() {
  try {
    while (true) {
      if (!conn_) {
        if (!Wait(1000, false)) return;
        try {
          Connect();
        } catch (const Error& error) {
          spdlog::debug("{}", error.what());
          continue;
        }
        on_notify_("");  // the notifications sent while it was away are lost
      }
      if (!Wait(-1, true)) return;
      if (!PQconsumeInput(conn_)) {
        spdlog::warn("PostgreSQL: the listener on {} lost its connection: {}; connecting again", channel_,
                     PgMessageLine(PQerrorMessage(conn_)));
        PQfinish(conn_);
        conn_ = nullptr;
        continue;
      }
      while (PGnotify* notification = PQnotifies(conn_)) {
        const std::string payload = notification->extra ? notification->extra : "";
        PQfreemem(notification);
        on_notify_(payload);
      }
    }
  } catch (const std::exception& error) {
    spdlog::error("PostgreSQL: the listener on {} stopped: {}", channel_, error.what());
  }
}

}  // namespace loom::server
