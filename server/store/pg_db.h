#pragma once
// The store's SqlDb on PostgreSQL through libpq (sql_db.h): one connection, SQLite's placeholders
// translated, values bound as text except a Blob, which goes as bytes (bytea) and
// reads back as its bytes; writer transactions serialised by an advisory lock.
//
// Every failure becomes a loom::Error naming the statement: kUnavailable when the
// server cannot be reached or the connection is lost (naming the server, never the
// password), and for a serialization failure or deadlock (the transaction may be
// retried); kInternal otherwise. The connection stays usable after a failed statement.
// A lost connection is made again at the next statement, but not inside the
// transaction it was lost in: every statement of that one, its commit included, is
// kUnavailable until it is rolled back.
//
// Not thread-safe: each owner serialises access with its own mutex.

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "server/store/sql_db.h"

struct pg_conn;
struct pg_result;

namespace loom::server {

// The first line of a libpq message, without its trailing newline.
std::string PgMessageLine(const char* message);

// SQLite's placeholders in `sql` as PostgreSQL's: `?` -> $1, $2, … in order, `?N` -> $N;
// none inside quoted literals or identifiers.
std::string ToPgPlaceholders(std::string_view sql);

// The rows of one executed statement (all fetched).
class PgRows final : public SqlRows {
 public:
  explicit PgRows(pg_result* result);
  PgRows(const PgRows&) = delete;
  PgRows& operator=(const PgRows&) = delete;
  ~PgRows() override;

  bool Step() override;
  int64_t Int(int column) const override;
  double Double(int column) const override;
  // A text column as it is, a bytea column as its bytes, NULL as "".
  std::string Text(int column) const override;

 private:
  // The current row's `column`, nullptr for NULL.
  const char* Value(int column) const;

  pg_result* result_;
  int rows_ = 0;
  int row_ = -1;
};

class PgDb final : public SqlDb {
 public:
  // Connects with a libpq connection string or postgresql:// URI.
  // Error(kUnavailable) when the server cannot be reached.
  explicit PgDb(const std::string& conninfo);
  ~PgDb() override;
  PgDb(const PgDb&) = delete;
  PgDb& operator=(const PgDb&) = delete;

  SqlDialect dialect() const override { return SqlDialect::kPostgres; }
  void Exec(std::string_view sql) override;
  std::unique_ptr<SqlRows> Execute(std::string_view sql, const std::vector<SqlValue>& values) override;
  int64_t Changes() const override { return changes_; }
  // pg_notify, delivered at commit; Listen is a PgListener (pg_listener.h) on a
  // connection of its own.
  void Notify(std::string_view channel, std::string_view payload) override;
  std::unique_ptr<SqlListener> Listen(const std::string& channel,
                                      std::function<void(const std::string& payload)> on_notify) override;

  // "host:port/database" for messages: never the password.
  const std::string& where() const { return where_; }

 protected:
  // BEGIN, then the store's advisory lock, held to the transaction's end: writers
  // on every connection to this database take turns, as SQLite's do.
  void Begin() override;
  void Commit() override;
  void Rollback() noexcept override;

 private:
  void SetUpSession();
  // A connection lost earlier is made again (kUnavailable if the server is still away,
  // or inside the transaction it was lost in).
  void Reconnect();
  // Throws the Error for a failed `result` (freed) of `sql`.
  [[noreturn]] void Fail(pg_result* result, std::string_view sql);

  const std::string conninfo_;  // for the listeners' connections
  pg_conn* conn_ = nullptr;
  bool broken_ = false;  // the connection failed: make it again before the next statement
  bool in_transaction_ = false;  // a connection lost inside one is made again only once it ended
  int64_t changes_ = 0;
  std::string where_;
};

}  // namespace loom::server
