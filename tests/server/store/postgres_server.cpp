#include "tests/server/store/postgres_server.h"

#include <pwd.h>
#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <stdexcept>

#include "server/store/pg_db.h"

namespace loom::server {
namespace {

constexpr char kPort[] = "5432";  // names the socket file only: no TCP

// Debian keeps the server's programs off PATH, under /usr/lib/postgresql/<version>/bin.
std::filesystem::path BinDir() {
  std::filesystem::path newest;
  if (std::filesystem::is_directory("/usr/lib/postgresql")) {
    for (const auto& entry : std::filesystem::directory_iterator("/usr/lib/postgresql")) {
      if (std::filesystem::exists(entry.path() / "bin" / "pg_ctl") && entry.path() > newest) newest = entry.path();
    }
  }
  if (newest.empty()) {
    throw std::runtime_error("no PostgreSQL server under /usr/lib/postgresql (scripts/setup.sh --with-postgresql)");
  }
  return newest / "bin";
}

std::string Quote(const std::string& text) { return "'" + text + "'"; }

}  // namespace

PostgresServer::PostgresServer() {
  static std::atomic<int> servers{0};
  dir_ = std::filesystem::path("/tmp") /
         ("loom-pg-" + std::to_string(::getpid()) + "-" + std::to_string(servers++));
  std::filesystem::remove_all(dir_);
  std::filesystem::create_directories(dir_);
  if (::geteuid() == 0) {
    const passwd* postgres = ::getpwnam("postgres");
    if (!postgres) throw std::runtime_error("running as root, and there is no postgres user to run PostgreSQL as");
    if (::chown(dir_.c_str(), postgres->pw_uid, postgres->pw_gid) != 0) {
      throw std::runtime_error("cannot give " + dir_.string() + " to postgres");
    }
  }
  RunTool("initdb -D " + Quote((dir_ / "data").string()) + " -A trust -U loom --no-sync --no-instructions");
  Restart();
}

PostgresServer::~PostgresServer() {
  try {
    Kill();
  } catch (const std::exception&) {
  }
  std::error_code ignored;
  std::filesystem::remove_all(dir_, ignored);
}

std::string PostgresServer::ConnInfo(const std::string& database) const {
  return "host=" + dir_.string() + " port=" + kPort + " user=loom dbname=" + database + " connect_timeout=10";
}

void PostgresServer::CreateDatabase(const std::string& name) const {
  PgDb(ConnInfo()).Exec("CREATE DATABASE " + name);
}

void PostgresServer::Kill() {
  if (!running_) return;
  running_ = false;
  RunTool("pg_ctl -D " + Quote((dir_ / "data").string()) + " -m immediate -w stop");
}

void PostgresServer::Restart() {
  // fsync off: a test cluster need not survive a power loss, only a process crash.
  RunTool("pg_ctl -D " + Quote((dir_ / "data").string()) + " -l " + Quote((dir_ / "log").string()) +
          " -w -o \"-c listen_addresses='' -k " + dir_.string() + " -p " + kPort +
          " -c fsync=off -c max_connections=200\" start");
  running_ = true;
}

std::string FreshPostgresDatabase() {
  static PostgresServer server;  // destroyed at exit: stopped and removed
  static int databases = 0;
  const std::string name = "loom_" + std::to_string(++databases);
  server.CreateDatabase(name);
  return server.ConnInfo(name);
}

void PostgresServer::RunTool(const std::string& arguments) const {
  std::string command = (BinDir() / "").string() + arguments;
  if (::geteuid() == 0) command = "runuser -u postgres -- " + command;
  command += " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) throw std::runtime_error("cannot run " + command);
  std::string output;
  char buffer[4096];
  while (size_t n = fread(buffer, 1, sizeof buffer, pipe)) output.append(buffer, n);
  if (pclose(pipe) != 0) {
    std::string log;
    if (FILE* file = std::fopen((dir_ / "log").c_str(), "r")) {
      while (size_t n = fread(buffer, 1, sizeof buffer, file)) log.append(buffer, n);
      std::fclose(file);
    }
    throw std::runtime_error(command + " failed: " + output + log);
  }
}

}  // namespace loom::server
