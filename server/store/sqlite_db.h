#pragma once
// The store's SqlDb on SQLite (sql_db.h): one connection in WAL mode, prepared
// statements with typed binding, and BEGIN IMMEDIATE transactions that roll back
// unless committed. The connection holds an exclusive lock on
// "<database>.lock" while open: a second server on the same data directory would
// requeue the first one's leases, so it is refused (kUnavailable) instead. Every SQLite failure becomes a loom::Error naming the
// statement: kUnavailable for a full disk or an I/O error, kInternal otherwise.
//
// Not thread-safe: each owner serialises access with its own mutex.

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "server/store/sql_db.h"

struct sqlite3;
struct sqlite3_stmt;

namespace loom::server {

// One prepared statement and its rows.
class Statement final : public SqlRows {
 public:
  Statement(sqlite3* db, std::string_view sql);
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;
  ~Statement() override;

  // Binds parameter `index` (from 1). A Blob binds as TEXT with its length: any
  // bytes round-trip, since SQLite does not validate UTF-8.
  void Bind(int index, const SqlValue& value);

  bool Step() override;
  int64_t Int(int column) const override;
  double Double(int column) const override;
  std::string Text(int column) const override;

 private:
  sqlite3* db_;
  sqlite3_stmt* stmt_ = nullptr;
  std::string sql_;
};

class SqliteDb final : public SqlDb {
 public:
  // Opens or creates `path`, in WAL mode with synchronous=NORMAL: a committed
  // transaction survives a process crash (kill -9); only a power loss may lose the
  // last ones. The lock dies with the process, so a crash never leaves it held.
  explicit SqliteDb(const std::filesystem::path& path);
  ~SqliteDb() override;
  SqliteDb(const SqliteDb&) = delete;
  SqliteDb& operator=(const SqliteDb&) = delete;

  SqlDialect dialect() const override { return SqlDialect::kSqlite; }
  void Exec(std::string_view sql) override;
  std::unique_ptr<SqlRows> Execute(std::string_view sql, const std::vector<SqlValue>& values) override;
  int64_t Changes() const override;
  // One process per database: no one else to tell.
  void Notify(std::string_view, std::string_view) override {}
  std::unique_ptr<SqlListener> Listen(const std::string&, std::function<void(const std::string&)>) override {
    return nullptr;
  }

 protected:
  void Begin() override;  // BEGIN IMMEDIATE: the write lock now, not at the first write
  void Commit() override;
  void Rollback() noexcept override;

 private:
  int lock_fd_ = -1;
  sqlite3* db_ = nullptr;
};

}  // namespace loom::server
