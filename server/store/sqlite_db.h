#pragma once
// A small RAII layer over SQLite for the store: one connection in WAL mode,
// prepared statements with typed binding, and BEGIN IMMEDIATE transactions that
// roll back unless committed. The connection holds an exclusive lock on
// "<database>.lock" while open: a second server on the same data directory would
// requeue the first one's leases, so it is refused (kUnavailable) instead. Every SQLite failure becomes a loom::Error naming the
// statement: kUnavailable for a full disk or an I/O error, kInternal otherwise.
//
// Not thread-safe: each owner serialises access with its own mutex.

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

struct sqlite3;
struct sqlite3_stmt;

namespace loom::server {

class Statement {
 public:
  Statement(sqlite3* db, std::string_view sql);
  Statement(Statement&& other) noexcept;
  Statement& operator=(Statement&&) = delete;
  ~Statement();

  // Binds parameters 1, 2, ... in order.
  template <typename... Args>
  Statement& BindAll(const Args&... args) {
    int index = 0;
    (Bind(++index, args), ...);
    return *this;
  }
  void Bind(int index, int64_t value);
  void Bind(int index, int value) { Bind(index, static_cast<int64_t>(value)); }
  void Bind(int index, uint32_t value) { Bind(index, static_cast<int64_t>(value)); }
  void Bind(int index, uint64_t value) { Bind(index, static_cast<int64_t>(value)); }
  void Bind(int index, bool value) { Bind(index, static_cast<int64_t>(value)); }
  void Bind(int index, double value);
  void Bind(int index, std::string_view text);
  void Bind(int index, const std::string& text) { Bind(index, std::string_view(text)); }
  void Bind(int index, const char* text) { Bind(index, std::string_view(text)); }

  // Advances to the next row; false when done.
  bool Step();
  // Steps to completion (for statements that return no rows).
  void Run();

  int64_t Int(int column) const;
  double Double(int column) const;
  // TEXT or BLOB column as bytes.
  std::string Text(int column) const;

 private:
  sqlite3* db_;
  sqlite3_stmt* stmt_ = nullptr;
  std::string sql_;
};

class SqliteDb {
 public:
  // Opens or creates `path`, in WAL mode with synchronous=NORMAL: a committed
  // transaction survives a process crash (kill -9); only a power loss may lose the
  // last ones. The lock dies with the process, so a crash never leaves it held.
  explicit SqliteDb(const std::filesystem::path& path);
  ~SqliteDb();
  SqliteDb(const SqliteDb&) = delete;
  SqliteDb& operator=(const SqliteDb&) = delete;

  // One or more statements, no parameters (schema).
  void Exec(std::string_view sql);

  template <typename... Args>
  Statement Query(std::string_view sql, const Args&... args) {
    Statement statement(db_, sql);
    statement.BindAll(args...);
    return statement;
  }
  template <typename... Args>
  void Run(std::string_view sql, const Args&... args) {
    Query(sql, args...).Run();
  }

  // Rows changed by the last INSERT/UPDATE/DELETE.
  int64_t Changes() const;

  class Transaction {
   public:
    explicit Transaction(SqliteDb& db);
    ~Transaction();
    Transaction(const Transaction&) = delete;
    Transaction& operator=(const Transaction&) = delete;
    void Commit();

   private:
    SqliteDb& db_;
    bool done_ = false;
  };

 private:
  int lock_fd_ = -1;
  sqlite3* db_ = nullptr;
};

}  // namespace loom::server
