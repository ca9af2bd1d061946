#include "server/store/store_migration.h"

#include <memory>

#include "core/util/error.h"
#include "server/store/artifact_store.h"
#include "server/store/clock.h"
#include "server/store/fabric_cache.h"
#include "server/store/job_queue.h"
#include "server/store/pg_db.h"
#include "server/store/sqlite_db.h"

namespace loom::server {
namespace {

// The tables copied from each SQLite file, parents before the rows that refer to them.
const std::vector<std::pair<std::string, std::vector<std::string>>> kTables = {
    {"jobs.db", {"jobs", "job_deps", "job_failed_workers", "job_log", "leases"}},
    {"cache.db", {"artifacts", "artifact_pins", "fabrics", "fabric_files"}},
};

// Identity columns whose sequence must go on after the copied rows (SQLite's
// AUTOINCREMENT remembers the largest ever given in sqlite_sequence).
const std::vector<std::pair<std::string, std::string>> kIdentities = {{"jobs", "seq"}, {"leases", "token"}};

struct Column {
  std::string name;
  std::string pg_type;  // information_schema's data_type
  bool nullable = false;
};

// The columns both databases' `table` have, with PostgreSQL's types.
std::vector<Column> SharedColumns(SqlDb& sqlite, SqlDb& pg, const std::string& table) {
  std::vector<Column> columns;
  for (auto pg_columns = pg.Query(
           "SELECT column_name, data_type, is_nullable FROM information_schema.columns "
           "WHERE table_schema = current_schema() AND table_name = ? ORDER BY ordinal_position",
           table);
       pg_columns.Step();) {
    auto in_sqlite =
        sqlite.Query("SELECT COUNT(*) FROM pragma_table_info(?) WHERE name = ?", table, pg_columns.Text(0));
    in_sqlite.Step();
    if (in_sqlite.Int(0) > 0) columns.push_back({pg_columns.Text(0), pg_columns.Text(1), pg_columns.Text(2) == "YES"});
  }
  return columns;
}

// Copies every row of `table`, in SQLite's rowid order (job_deps keeps the order
// given); returns how many.
int64_t CopyTable(SqlDb& sqlite, SqlDb& pg, const std::string& table) {
  const std::vector<Column> columns = SharedColumns(sqlite, pg, table);
  std::string names, placeholders;
  for (const Column& column : columns) {
    names += (names.empty() ? "" : ", ") + column.name;
    // A nullable text column (client_request_id) holds NULL, never "", for "none".
    placeholders += std::string(placeholders.empty() ? "" : ", ") + (column.nullable ? "NULLIF(?, '')" : "?");
  }
  const std::string insert = "INSERT INTO " + table + " (" + names + ") VALUES (" + placeholders + ")";
  int64_t rows = 0;
  for (auto select = sqlite.Query("SELECT " + names + " FROM " + table + " ORDER BY rowid"); select.Step(); ++rows) {
    std::vector<std::string> texts(columns.size());
    std::vector<SqlValue> values;
    for (size_t i = 0; i < columns.size(); ++i) {
      const int c = static_cast<int>(i);
      const std::string& type = columns[i].pg_type;
      if (type == "bigint" || type == "integer") {
        values.push_back(select.Int(c));
      } else if (type == "double precision") {
        values.push_back(select.Double(c));
      } else {
        texts[i] = select.Text(c);
        values.push_back(type == "bytea" ? SqlValue(Blob{texts[i]}) : SqlValue(std::string_view(texts[i])));
      }
    }
    pg.Execute(insert, values);
  }
  return rows;
}

// The largest value `table`.`column` ever had in SQLite.
int64_t LargestEver(SqlDb& sqlite, const std::string& table, const std::string& column) {
  auto largest = sqlite.Query("SELECT MAX(v) FROM (SELECT MAX(" + column + ") AS v FROM " + table +
                                  " UNION ALL SELECT seq FROM sqlite_sequence WHERE name = ?)",
                              table);
  largest.Step();
  return largest.Int(0);
}

}  // namespace

MigratedRows MigrateSqliteStore(const std::filesystem::path& data_dir, const std::string& conninfo) {
  for (const auto& [file, tables] : kTables) {
    if (!std::filesystem::exists(data_dir / file)) {
      throw Error(ErrorCode::kNotFound, "--data: no SQLite store to migrate: " + (data_dir / file).string() +
                                            " does not exist");
    }
  }
  // The PostgreSQL store's tables, made as a server makes them.
  {
    SystemClock clock;
    ArtifactStore artifacts(data_dir, std::make_unique<PgDb>(conninfo));
    FabricCache cache(artifacts, clock);
    JobQueue queue(std::make_unique<PgDb>(conninfo), clock);
  }
  PgDb pg(conninfo);
  SqlDb::Transaction txn(pg);
  for (const char* table : {"jobs", "artifacts", "fabrics"}) {
    auto count = pg.Query(std::string("SELECT COUNT(*) FROM ") + table);
    count.Step();
    if (count.Int(0) > 0) {
      throw Error(ErrorCode::kFailedPrecondition, "--store: the PostgreSQL store at " + pg.where() + " already holds " +
                                                      std::to_string(count.Int(0)) + " " + table +
                                                      " rows; migrate into an empty database");
    }
  }
  MigratedRows copied;
  for (const auto& [file, tables] : kTables) {
    SqliteDb sqlite(data_dir / file);
    for (const std::string& table : tables) copied.emplace_back(table, CopyTable(sqlite, pg, table));
    if (file != "jobs.db") continue;
    for (const auto& [table, column] : kIdentities) {
      const int64_t largest = LargestEver(sqlite, table, column);
      if (largest > 0) {
        pg.Run("SELECT setval(pg_get_serial_sequence(?, ?), ?)", table, column, largest);
      }
    }
    pg.Run("SELECT setval('job_version', MAX(version)) FROM jobs HAVING MAX(version) > 0");
  }
  txn.Commit();
  return copied;
}

}  // namespace loom::server
