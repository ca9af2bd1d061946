#pragma once
// A small RAII layer over libpq for the store's PostgreSQL backend (issue 30), the
// counterpart of sqlite_db.h: one connection, statements written with SQLite's
// placeholders (`?` in order, or `?N`) and bound by value, rows read by column, and
// transactions that roll back unless committed. Values go as text, except Blob, which
// goes as bytes (bytea); a bytea column reads back as its bytes.
//
// Every failure becomes a loom::Error naming the statement: kUnavailable when the
// server cannot be reached or the connection is lost (naming the server, never the
// password), and for a serialization failure or deadlock (the transaction may be
// retried); kInternal otherwise. The connection stays usable after a failed statement.
//
// Not thread-safe: each owner serialises access with its own mutex.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

struct pg_conn;
struct pg_result;

namespace loom::server {

// Bytes bound as bytea (may hold NUL).
struct Blob {
  std::string_view bytes;
};

// One bound parameter: nullopt is SQL NULL.
struct PgParam {
  std::optional<std::string> value;
  bool binary = false;
};

PgParam ToPgParam(int64_t value);
PgParam ToPgParam(double value);
PgParam ToPgParam(std::string_view text);
PgParam ToPgParam(Blob blob);
inline PgParam ToPgParam(int value) { return ToPgParam(static_cast<int64_t>(value)); }
inline PgParam ToPgParam(uint32_t value) { return ToPgParam(static_cast<int64_t>(value)); }
inline PgParam ToPgParam(uint64_t value) { return ToPgParam(static_cast<int64_t>(value)); }
inline PgParam ToPgParam(bool value) { return ToPgParam(static_cast<int64_t>(value)); }
inline PgParam ToPgParam(const std::string& text) { return ToPgParam(std::string_view(text)); }
inline PgParam ToPgParam(const char* text) { return ToPgParam(std::string_view(text)); }

// SQLite's placeholders in `sql` as PostgreSQL's: `?` -> $1, $2, … in order, `?N` -> $N;
// none inside quoted literals or identifiers.
std::string ToPgPlaceholders(std::string_view sql);

// The rows of one executed statement.
class PgRows {
 public:
  PgRows(PgRows&& other) noexcept;
  PgRows& operator=(PgRows&&) = delete;
  ~PgRows();

  // Advances to the next row; false when done.
  bool Step();
  int64_t Int(int column) const;
  double Double(int column) const;
  // A text column as it is, a bytea column as its bytes.
  std::string Text(int column) const;
  bool IsNull(int column) const;
  // Rows the statement changed (INSERT/UPDATE/DELETE).
  int64_t Changes() const { return changes_; }

 private:
  friend class PgDb;
  explicit PgRows(pg_result* result);
  void RequireRow(int column) const;

  pg_result* result_;
  int rows_ = 0;
  int row_ = -1;
  int64_t changes_ = 0;
};

class PgDb {
 public:
  // Connects with a libpq connection string or postgresql:// URI.
  // Error(kUnavailable) when the server cannot be reached.
  explicit PgDb(const std::string& conninfo);
  ~PgDb();
  PgDb(const PgDb&) = delete;
  PgDb& operator=(const PgDb&) = delete;

  // One or more statements, no parameters (schema).
  void Exec(std::string_view sql);

  template <typename... Args>
  PgRows Query(std::string_view sql, const Args&... args) {
    return Execute(sql, {ToPgParam(args)...});
  }
  template <typename... Args>
  int64_t Run(std::string_view sql, const Args&... args) {
    return Query(sql, args...).Changes();
  }
  PgRows Execute(std::string_view sql, const std::vector<PgParam>& params);

  // "host:port/database" for messages: never the password.
  const std::string& where() const { return where_; }

  class Transaction {
   public:
    explicit Transaction(PgDb& db);
    ~Transaction();
    Transaction(const Transaction&) = delete;
    Transaction& operator=(const Transaction&) = delete;
    void Commit();

   private:
    PgDb& db_;
    bool done_ = false;
  };

 private:
  void SetUpSession();
  // A connection lost earlier is made again (kUnavailable if the server is still away).
  void Reconnect();
  // Throws the Error for a failed `result` (freed) of `sql`.
  [[noreturn]] void Fail(pg_result* result, std::string_view sql);

  pg_conn* conn_ = nullptr;
  bool broken_ = false;  // the connection failed: make it again before the next statement
  std::string where_;
};

}  // namespace loom::server
