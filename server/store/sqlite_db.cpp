#include "server/store/sqlite_db.h"

#include <fcntl.h>
#include <sqlite3.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "core/util/error.h"

namespace loom::server {
namespace {

[[noreturn]] void Fail(sqlite3* db, int rc, std::string_view what) {
  const int primary = rc & 0xff;
  const ErrorCode code =
      (primary == SQLITE_FULL || primary == SQLITE_IOERR || primary == SQLITE_CANTOPEN)
          ? ErrorCode::kUnavailable
          : ErrorCode::kInternal;
  throw Error(code, "sqlite: " + std::string(what) + ": " + (db ? sqlite3_errmsg(db) : sqlite3_errstr(rc)));
}

}  // namespace

Statement::Statement(sqlite3* db, std::string_view sql) : db_(db), sql_(sql) {
  const int rc = sqlite3_prepare_v2(db_, sql.data(), static_cast<int>(sql.size()), &stmt_, nullptr);
  if (rc != SQLITE_OK) Fail(db_, rc, sql_);
}

Statement::~Statement() { sqlite3_finalize(stmt_); }

void Statement::Bind(int index, const SqlValue& value) {
  int rc = SQLITE_OK;
  if (const auto* number = std::get_if<int64_t>(&value)) {
    rc = sqlite3_bind_int64(stmt_, index, *number);
  } else if (const auto* real = std::get_if<double>(&value)) {
    rc = sqlite3_bind_double(stmt_, index, *real);
  } else {
    const std::string_view text =
        std::holds_alternative<Blob>(value) ? std::get<Blob>(value).bytes : std::get<std::string_view>(value);
    rc = sqlite3_bind_text64(stmt_, index, text.data(), text.size(), SQLITE_TRANSIENT, SQLITE_UTF8);
  }
  if (rc != SQLITE_OK) Fail(db_, rc, sql_);
}

bool Statement::Step() {
  const int rc = sqlite3_step(stmt_);
  if (rc == SQLITE_ROW) return true;
  if (rc == SQLITE_DONE) return false;
  Fail(db_, rc, sql_);
}

int64_t Statement::Int(int column) const { return sqlite3_column_int64(stmt_, column); }

double Statement::Double(int column) const { return sqlite3_column_double(stmt_, column); }

std::string Statement::Text(int column) const {
  const void* data = sqlite3_column_blob(stmt_, column);
  const int size = sqlite3_column_bytes(stmt_, column);
  return data ? std::string(static_cast<const char*>(data), static_cast<size_t>(size)) : std::string();
}

SqliteDb::SqliteDb(const std::filesystem::path& path) {
  std::error_code ec;
  std::filesystem::create_directories(path.parent_path(), ec);
  if (ec) throw Error(ErrorCode::kUnavailable, "cannot create " + path.parent_path().string() + ": " + ec.message());
  const std::string lock_path = path.string() + ".lock";
  lock_fd_ = ::open(lock_path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (lock_fd_ < 0) {
    throw Error(ErrorCode::kUnavailable, "cannot open " + lock_path + ": " + std::strerror(errno));
  }
  if (::flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
    ::close(lock_fd_);
    // Not kUnavailable (exit 4, "no GL, server unreachable"): the directory is in a
    // state this server cannot start in until the other one stops (exit 5).
    throw Error(ErrorCode::kFailedPrecondition,
                path.string() + " is in use by another process (one loom-server per data directory)");
  }
  const int rc = sqlite3_open_v2(path.c_str(), &db_,
                                 SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_NOMUTEX, nullptr);
  if (rc != SQLITE_OK) {
    const std::string message = db_ ? sqlite3_errmsg(db_) : sqlite3_errstr(rc);
    sqlite3_close(db_);
    ::close(lock_fd_);
    throw Error(ErrorCode::kUnavailable, "cannot open database " + path.string() + ": " + message);
  }
  sqlite3_busy_timeout(db_, 5000);
  try {
    Exec("PRAGMA journal_mode=WAL; PRAGMA synchronous=NORMAL; PRAGMA foreign_keys=ON;");
  } catch (...) {
    sqlite3_close(db_);
    ::close(lock_fd_);
    throw;
  }
}

SqliteDb::~SqliteDb() {
  sqlite3_close(db_);
  ::close(lock_fd_);
}

void SqliteDb::Exec(std::string_view sql) {
  const std::string text(sql);
  char* message = nullptr;
  const int rc = sqlite3_exec(db_, text.c_str(), nullptr, nullptr, &message);
  if (rc != SQLITE_OK) {
    const std::string reason = message ? message : sqlite3_errstr(rc);
    sqlite3_free(message);
    throw Error(ErrorCode::kInternal, "sqlite: " + text + ": " + reason);
  }
}

std::unique_ptr<SqlRows> SqliteDb::Execute(std::string_view sql, const std::vector<SqlValue>& values) {
  auto statement = std::make_unique<Statement>(db_, sql);
  for (size_t i = 0; i < values.size(); ++i) statement->Bind(static_cast<int>(i + 1), values[i]);
  return statement;
}

int64_t SqliteDb::Changes() const { return sqlite3_changes64(db_); }

void SqliteDb::Begin() { Exec("BEGIN IMMEDIATE"); }

void SqliteDb::Commit() { Exec("COMMIT"); }

void SqliteDb::Rollback() noexcept { sqlite3_exec(db_, "ROLLBACK", nullptr, nullptr, nullptr); }

}  // namespace loom::server
