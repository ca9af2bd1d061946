#include "server/store/pg_db.h"

#include <fmt/format.h>
#include <libpq-fe.h>
#include <spdlog/spdlog.h>

#include <cctype>
#include <cstdlib>
#include <cstring>

#include "core/util/error.h"
#include "server/store/pg_listener.h"

namespace loom::server {
namespace {

constexpr Oid kByteaOid = 17;

// "host:port/database" of a connection, for messages.
std::string Where(const PGconn* conn) {
  const char* host = PQhost(conn);
  const char* port = PQport(conn);
  const char* database = PQdb(conn);
  return fmt::format("{}:{}/{}", host ? host : "", port ? port : "", database ? database : "");
}

int HexValue(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

}  // namespace

std::string PgMessageLine(const char* message) {
  std::string line = message ? message : "";
  return line.substr(0, line.find('\n'));
}

std::string ToPgPlaceholders(std::string_view sql) {
  std::string out;
  out.reserve(sql.size() + 8);
  int next = 0;
  char quote = 0;  // inside '…' or "…"
  for (size_t i = 0; i < sql.size(); ++i) {
    const char c = sql[i];
    if (quote) {
      out += c;
      if (c == quote) quote = 0;  // a doubled quote closes and reopens: the same
    } else if (c == '\'' || c == '"') {
      quote = c;
      out += c;
    } else if (c == '?') {
      size_t end = i + 1;
      while (end < sql.size() && std::isdigit(static_cast<unsigned char>(sql[end]))) ++end;
      if (end > i + 1) {
        out += '$';
        out += sql.substr(i + 1, end - i - 1);
        i = end - 1;
      } else {
        out += '$' + std::to_string(++next);
      }
    } else {
      out += c;
    }
  }
  return out;
}

PgRows::PgRows(pg_result* result) : result_(result), rows_(PQntuples(result)) {}

PgRows::~PgRows() { PQclear(result_); }

bool PgRows::Step() { return ++row_ < rows_; }

const char* PgRows::Value(int column) const {
  if (row_ < 0 || row_ >= rows_ || column < 0 || column >= PQnfields(result_)) {
    throw Error(ErrorCode::kInternal, fmt::format("PostgreSQL: no row {} column {}", row_, column));
  }
  return PQgetisnull(result_, row_, column) ? nullptr : PQgetvalue(result_, row_, column);
}

int64_t PgRows::Int(int column) const {
  const char* text = Value(column);
  if (!text) return 0;
  // A boolean reads as t/f.
  if (text[0] == 't' || text[0] == 'f') return text[0] == 't';
  return std::strtoll(text, nullptr, 10);
}

double PgRows::Double(int column) const {
  const char* text = Value(column);
  return text ? std::strtod(text, nullptr) : 0;
}

std::string PgRows::Text(int column) const {
  const char* text = Value(column);
  if (!text) return "";
  const int length = PQgetlength(result_, row_, column);
  if (PQftype(result_, column) != kByteaOid) return std::string(text, length);
  // bytea in text form: "\x" and two hex digits a byte.
  if (length < 2 || text[0] != '\\' || text[1] != 'x') {
    throw Error(ErrorCode::kInternal, "PostgreSQL: a bytea column not in hex form");
  }
  std::string bytes;
  bytes.reserve((length - 2) / 2);
  for (int i = 2; i + 1 < length; i += 2) {
    bytes += static_cast<char>(HexValue(text[i]) * 16 + HexValue(text[i + 1]));
  }
  return bytes;
}

PgDb::PgDb(const std::string& conninfo) : conninfo_(conninfo) {
  conn_ = PQconnectdb(conninfo.c_str());
  if (!conn_) throw Error(ErrorCode::kUnavailable, "PostgreSQL: out of memory connecting");
  where_ = Where(conn_);
  if (PQstatus(conn_) != CONNECTION_OK) {
    const std::string message = PgMessageLine(PQerrorMessage(conn_));
    PQfinish(conn_);
    conn_ = nullptr;
    throw Error(ErrorCode::kUnavailable, "PostgreSQL at " + where_ + ": cannot connect: " + message);
  }
  PQsetNoticeProcessor(
      conn_, [](void*, const char* message) { spdlog::debug("PostgreSQL: {}", PgMessageLine(message)); }, nullptr);
  SetUpSession();
}

void PgDb::SetUpSession() {
  // The store's statements are short; a lock held by a stuck server must not hang
  // every other.
  Exec("SET lock_timeout = '30s'; SET client_min_messages = warning");
}

void PgDb::Reconnect() {
  if (PQstatus(conn_) == CONNECTION_OK && !broken_) return;
  if (in_transaction_) {
    // Run on a new connection, the rest of it would commit on its own.
    throw Error(ErrorCode::kUnavailable,
                "PostgreSQL at " + where_ + ": the connection was lost inside a transaction, which is rolled back");
  }
  PQreset(conn_);
  if (PQstatus(conn_) != CONNECTION_OK) {
    throw Error(ErrorCode::kUnavailable,
                "PostgreSQL at " + where_ + ": connection lost: " + PgMessageLine(PQerrorMessage(conn_)));
  }
  broken_ = false;
  SetUpSession();
}

PgDb::~PgDb() {
  if (conn_) PQfinish(conn_);
}

void PgDb::Fail(pg_result* result, std::string_view sql) {
  const char* state = result ? PQresultErrorField(result, PG_DIAG_SQLSTATE) : nullptr;
  const std::string message = PgMessageLine(result ? PQresultErrorMessage(result) : PQerrorMessage(conn_));
  const std::string sqlstate = state ? state : "";
  if (result) PQclear(result);
  const std::string what = fmt::format("PostgreSQL at {}: {} (in: {})", where_, message, sql.substr(0, 200));
  // No SQLSTATE, 57P01 admin_shutdown or 08xxx: the failure was the connection's,
  // not the statement's; the next statement reconnects.
  if (PQstatus(conn_) != CONNECTION_OK || sqlstate.empty() || sqlstate == "57P01" || sqlstate.starts_with("08")) {
    broken_ = true;
    throw Error(ErrorCode::kUnavailable, what);
  }
  // 40001 serialization_failure, 40P01 deadlock_detected, 55P03 lock_not_available:
  // try again.
  if (sqlstate == "40001" || sqlstate == "40P01" || sqlstate == "55P03") {
    throw Error(ErrorCode::kUnavailable, what);
  }
  throw Error(ErrorCode::kInternal, what);
}

void PgDb::Exec(std::string_view sql) {
  Reconnect();
  const std::string text(sql);
  pg_result* result = PQexec(conn_, text.c_str());
  const ExecStatusType status = result ? PQresultStatus(result) : PGRES_FATAL_ERROR;
  if (status != PGRES_COMMAND_OK && status != PGRES_TUPLES_OK) Fail(result, sql);
  PQclear(result);
}

std::unique_ptr<SqlRows> PgDb::Execute(std::string_view sql, const std::vector<SqlValue>& values) {
  Reconnect();
  const std::string text = ToPgPlaceholders(sql);
  std::vector<std::string> texts(values.size());
  std::vector<const char*> pointers(values.size());
  std::vector<int> lengths(values.size()), formats(values.size());
  for (size_t i = 0; i < values.size(); ++i) {
    if (const auto* number = std::get_if<int64_t>(&values[i])) {
      texts[i] = std::to_string(*number);
    } else if (const auto* real = std::get_if<double>(&values[i])) {
      texts[i] = fmt::format("{:.17g}", *real);
    } else if (const auto* blob = std::get_if<Blob>(&values[i])) {
      texts[i] = std::string(blob->bytes);
      formats[i] = 1;  // binary: the bytes as they are
    } else {
      texts[i] = std::string(std::get<std::string_view>(values[i]));
    }
    pointers[i] = texts[i].data();
    lengths[i] = static_cast<int>(texts[i].size());
  }
  pg_result* result = PQexecParams(conn_, text.c_str(), static_cast<int>(values.size()), nullptr, pointers.data(),
                                   lengths.data(), formats.data(), /*resultFormat=*/0);
  const ExecStatusType status = result ? PQresultStatus(result) : PGRES_FATAL_ERROR;
  if (status != PGRES_COMMAND_OK && status != PGRES_TUPLES_OK) Fail(result, sql);
  const char* changed = PQcmdTuples(result);
  changes_ = changed && *changed ? std::strtoll(changed, nullptr, 10) : 0;
  return std::make_unique<PgRows>(result);
}

void PgDb::Notify(std::string_view channel, std::string_view payload) {
  Run("SELECT pg_notify(?, ?)", channel, payload);
}

std::unique_ptr<SqlListener> PgDb::Listen(const std::string& channel,
                                          std::function<void(const std::string& payload)> on_notify) {
  return std::make_unique<PgListener>(conninfo_, channel, std::move(on_notify));
}

void PgDb::Begin() {
  Exec("BEGIN");
  in_transaction_ = true;
  try {
    // One key for the whole store: 'LOOM'.
    Exec("SELECT pg_advisory_xact_lock(1280266061)");
  } catch (...) {
    Rollback();
    throw;
  }
}

void PgDb::Commit() {
  Exec("COMMIT");
  in_transaction_ = false;
}

void PgDb::Rollback() noexcept {
  const bool lost = broken_;
  in_transaction_ = false;
  if (lost) return;  // the transaction went with the connection; the next statement makes a new one
  try {
    Exec("ROLLBACK");
  } catch (const Error&) {
    // The connection is gone: so is the transaction.
  }
}

}  // namespace loom::server
