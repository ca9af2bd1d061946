#pragma once
// A real PostgreSQL server for the store's tests: Debian's initdb and pg_ctl (the
// postgresql package; scripts/setup.sh --with-postgresql) start a fresh cluster in a
// temporary directory, listening on a Unix socket there only (no TCP port to clash).
// As root it runs as the postgres user, which initdb requires. Stopped and removed
// when destroyed.

#include <filesystem>
#include <string>

namespace loom::server {

class PostgresServer {
 public:
  // Starts the server (pg_ctl waits until it accepts connections); throws
  // std::runtime_error with its log when it does not start.
  PostgresServer();
  ~PostgresServer();
  PostgresServer(const PostgresServer&) = delete;
  PostgresServer& operator=(const PostgresServer&) = delete;

  // A libpq connection string for database `database` as the cluster's owner.
  std::string ConnInfo(const std::string& database = "postgres") const;
  // Creates a database (CREATE DATABASE through psql's library: libpq).
  void CreateDatabase(const std::string& name) const;

  // pg_ctl stop -m immediate: as a crash would, without a checkpoint.
  void Kill();
  // Starts it again on the same data (after Kill).
  void Restart();

 private:
  // Runs a PostgreSQL program (as postgres when root); throws with its output on failure.
  void RunTool(const std::string& arguments) const;

  std::filesystem::path dir_;
  bool running_ = false;
};

// A new empty database on this process's own PostgreSQL server (started on first
// use, stopped at exit); its connection string.
std::string FreshPostgresDatabase();

}  // namespace loom::server
