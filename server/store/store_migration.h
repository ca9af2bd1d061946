#pragma once
// Moving a store from SQLite into PostgreSQL (loom-server --migrate-from-sqlite;
// docs/operations.md "PostgreSQL"): every row of the queue (jobs, their
// dependencies, logs, blocklists, leases) and of the catalogue (artifacts, pins, the
// fabric index) under DATA is copied, in one transaction, into a PostgreSQL store
// that holds nothing yet. The artifact files stay where they are, under DATA.
//
// Leases are copied as they stand: a worker that held one while the old server
// stopped reports through the new servers with its fencing token, or its lease
// expires as usual. Job ids, fencing tokens and job versions go on from where the
// SQLite store left them. Columns a PostgreSQL table has that an older SQLite store
// lacks take their defaults.
//
// Errors: kNotFound when DATA holds no SQLite store; the SQLite store's own error
// when a server still runs on it; kFailedPrecondition naming the rows found when
// the PostgreSQL store is not empty. A failure copies nothing.

#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace loom::server {

// Rows copied, by table, in the order copied.
using MigratedRows = std::vector<std::pair<std::string, int64_t>>;

MigratedRows MigrateSqliteStore(const std::filesystem::path& data_dir, const std::string& conninfo);

}  // namespace loom::server
