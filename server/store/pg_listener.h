#pragma once
// LISTEN on a PostgreSQL channel (SqlDb::Listen for PgDb): how servers sharing one
// store learn of each other's commits. A PgListener holds a connection of its own
// and a thread that waits on it and calls `on_notify` with each notification's
// payload, in order. A lost connection is made again (tried every second); then
// `on_notify("")` says that notifications may have been missed meanwhile.
//
// The constructor connects and listens before it returns (Error(kUnavailable) when
// the server cannot be reached); the destructor stops the thread, and `on_notify`
// is never called after it returns.

#include <functional>
#include <string>
#include <thread>

#include "server/store/sql_db.h"

struct pg_conn;

namespace loom::server {

class PgListener final : public SqlListener {
 public:
  PgListener(std::string conninfo, std::string channel, std::function<void(const std::string& payload)> on_notify);
  ~PgListener() override;
  PgListener(const PgListener&) = delete;
  PgListener& operator=(const PgListener&) = delete;

 private:
  // Connects and listens; Error(kUnavailable) on failure.
  void Connect();
  void Run();
  // Waits up to `timeout_ms` (-1: no limit) for the connection's socket (when
  // `on_socket`) or for the stop signal; false once stopping.
  bool Wait(int timeout_ms, bool on_socket);

  const std::string conninfo_;
  const std::string channel_;
  const std::function<void(const std::string&)> on_notify_;
  pg_conn* conn_ = nullptr;
  int stop_fd_ = -1;  // an eventfd: written once by the destructor
  std::thread thread_;
};

}  // namespace loom::server
