#pragma once
// What the store's tables ask of a SQL database (issue 30): SQLite for one server
// (sqlite_db.h), PostgreSQL for several on one database (pg_db.h). Statements are
// written with SQLite's placeholders (`?` in order, or `?N`) and values bind by
// type; rows are read by column; a writer transaction is one at a time across every
// process on the database, as SQLite's BEGIN IMMEDIATE is. Where the dialects differ
// (schema, a few functions), the store asks dialect(). Processes sharing a database
// tell each other of their commits through Notify and Listen.
//
// Not thread-safe: each owner serialises access with its own mutex.

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace loom::server {

// Bytes stored as bytes (bytea in PostgreSQL); they may hold NUL.
struct Blob {
  std::string_view bytes;
};

using SqlValue = std::variant<int64_t, double, std::string_view, Blob>;

inline SqlValue ToSqlValue(int64_t value) { return value; }
inline SqlValue ToSqlValue(int value) { return int64_t{value}; }
inline SqlValue ToSqlValue(uint32_t value) { return int64_t{value}; }
inline SqlValue ToSqlValue(uint64_t value) { return static_cast<int64_t>(value); }
inline SqlValue ToSqlValue(bool value) { return int64_t{value}; }
inline SqlValue ToSqlValue(double value) { return value; }
inline SqlValue ToSqlValue(std::string_view text) { return text; }
inline SqlValue ToSqlValue(const std::string& text) { return std::string_view(text); }
inline SqlValue ToSqlValue(const char* text) { return std::string_view(text); }
inline SqlValue ToSqlValue(Blob blob) { return blob; }

// The rows of one statement, read one at a time.
class SqlRows {
 public:
  virtual ~SqlRows() = default;
  // Advances to the next row; false when done.
  virtual bool Step() = 0;
  virtual int64_t Int(int column) const = 0;
  virtual double Double(int column) const = 0;
  // TEXT or BLOB column as bytes; NULL as "".
  virtual std::string Text(int column) const = 0;
};

// SqlRows by value: what SqlDb::Query returns.
class SqlQuery {
 public:
  explicit SqlQuery(std::unique_ptr<SqlRows> rows) : rows_(std::move(rows)) {}
  bool Step() { return rows_->Step(); }
  // Steps to completion (for statements that return no rows).
  void Run() {
    while (rows_->Step()) {
    }
  }
  int64_t Int(int column) const { return rows_->Int(column); }
  double Double(int column) const { return rows_->Double(column); }
  std::string Text(int column) const { return rows_->Text(column); }

 private:
  std::unique_ptr<SqlRows> rows_;
};

enum class SqlDialect { kSqlite, kPostgres };

// What SqlDb::Listen returns: notifications arrive while it lives, and never after
// its destructor returned.
class SqlListener {
 public:
  virtual ~SqlListener() = default;
};

class SqlDb {
 public:
  virtual ~SqlDb() = default;
  virtual SqlDialect dialect() const = 0;

  // One or more statements, no parameters (schema).
  virtual void Exec(std::string_view sql) = 0;
  virtual std::unique_ptr<SqlRows> Execute(std::string_view sql, const std::vector<SqlValue>& values) = 0;
  // Rows changed by the last INSERT/UPDATE/DELETE run to completion.
  virtual int64_t Changes() const = 0;

  template <typename... Args>
  SqlQuery Query(std::string_view sql, const Args&... args) {
    return SqlQuery(Execute(sql, {ToSqlValue(args)...}));
  }
  template <typename... Args>
  void Run(std::string_view sql, const Args&... args) {
    Query(sql, args...).Run();
  }

  // Sends `payload` on `channel` to every listener of this database, in any process,
  // once the open transaction commits (at once outside one).
  virtual void Notify(std::string_view channel, std::string_view payload) = 0;
  // Calls `on_notify` with each payload sent on `channel`, in order, on a thread of
  // its own; with "" after notifications may have been missed (a lost connection
  // made again). Null where the database is one process's (SQLite): that process
  // knows its own commits.
  virtual std::unique_ptr<SqlListener> Listen(const std::string& channel,
                                              std::function<void(const std::string& payload)> on_notify) = 0;

  // A writer transaction, rolled back unless committed.
  class Transaction {
   public:
    explicit Transaction(SqlDb& db) : db_(db) { db_.Begin(); }
    ~Transaction() {
      if (!done_) db_.Rollback();
    }
    Transaction(const Transaction&) = delete;
    Transaction& operator=(const Transaction&) = delete;
    void Commit() {
      db_.Commit();
      done_ = true;
    }

   private:
    SqlDb& db_;
    bool done_ = false;
  };

 protected:
  virtual void Begin() = 0;
  virtual void Commit() = 0;
  virtual void Rollback() noexcept = 0;
};

// Runs `ddl` (CREATE … IF NOT EXISTS) in one writer transaction: processes opening a
// shared database at once take turns, since PostgreSQL's IF NOT EXISTS does not
// guard against a concurrent CREATE.
inline void CreateSchema(SqlDb& db, std::string_view ddl) {
  SqlDb::Transaction txn(db);
  db.Exec(ddl);
  txn.Commit();
}

}  // namespace loom::server
