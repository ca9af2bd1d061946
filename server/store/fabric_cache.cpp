#include "server/store/fabric_cache.h"

#include <set>

#include "core/util/error.h"
#include "server/store/sqlite_db.h"

namespace loom::server {
namespace {

// In both SQLite's and PostgreSQL's dialect.
constexpr const char* kSchema = R"sql(
CREATE TABLE IF NOT EXISTS fabrics (
  key TEXT PRIMARY KEY,
  manifest_json TEXT NOT NULL,
  pinned INTEGER NOT NULL DEFAULT 0,
  created_ms BIGINT NOT NULL,
  last_used_ms BIGINT NOT NULL,
  use_seq BIGINT NOT NULL);  -- larger: used more recently
CREATE TABLE IF NOT EXISTS fabric_files (
  key TEXT NOT NULL REFERENCES fabrics(key),
  name TEXT NOT NULL,
  hash TEXT NOT NULL,
  PRIMARY KEY (key, name));
)sql";

constexpr const char* kNextUse = "(SELECT COALESCE(MAX(use_seq), 0) + 1 FROM fabrics)";

std::string PinOwner(const std::string& key) { return "fabric:" + key; }

void CheckFiles(const std::vector<FabricFile>& files) {
  if (files.empty()) throw Error(ErrorCode::kInvalidArgument, "a cached fabric needs at least one file");
  std::set<std::string> names;
  for (size_t i = 0; i < files.size(); ++i) {
    const std::string what = "files[" + std::to_string(i) + "]";
    const std::string& name = files[i].name;
    if (name.empty() || name == "." || name == ".." || name.find('/') != std::string::npos) {
      throw Error(ErrorCode::kInvalidArgument, what + ".name '" + name + "' is not a plain file name");
    }
    if (!names.insert(name).second) {
      throw Error(ErrorCode::kInvalidArgument, what + ".name '" + name + "' appears twice");
    }
    CheckArtifactHash(files[i].hash, what + ".hash");
  }
}

}  // namespace

FabricCache::FabricCache(ArtifactStore& artifacts, const Clock& clock) : artifacts_(artifacts), clock_(clock) {
  std::lock_guard lock(artifacts_.mu_);
  CreateSchema(*artifacts_.db_, kSchema);
}

std::optional<FabricEntry> FabricCache::FindLocked(const std::string& key) {
  SqlDb& db = *artifacts_.db_;
  auto row = db.Query("SELECT manifest_json, pinned, created_ms, last_used_ms FROM fabrics WHERE key = ?", key);
  if (!row.Step()) return std::nullopt;
  FabricEntry entry;
  entry.key = key;
  entry.manifest_json = row.Text(0);
  entry.pinned = row.Int(1) != 0;
  entry.created_ms = row.Int(2);
  entry.last_used_ms = row.Int(3);
  for (auto files = db.Query(
           "SELECT f.name, f.hash, COALESCE(a.size, 0) FROM fabric_files f LEFT JOIN artifacts a ON a.hash = f.hash "
           "WHERE f.key = ? ORDER BY f.name",
           key);
       files.Step();) {
    entry.files.push_back({files.Text(0), files.Text(1), static_cast<uint64_t>(files.Int(2))});
    entry.total_bytes += entry.files.back().bytes;
  }
  return entry;
}

void FabricCache::DeleteLocked(const std::string& key) {
  SqlDb& db = *artifacts_.db_;
  std::vector<std::string> hashes;
  for (auto files = db.Query("SELECT hash FROM fabric_files WHERE key = ?", key); files.Step();) {
    hashes.push_back(files.Text(0));
  }
  db.Run("DELETE FROM artifact_pins WHERE owner = ?", PinOwner(key));
  db.Run("DELETE FROM fabric_files WHERE key = ?", key);
  db.Run("DELETE FROM fabrics WHERE key = ?", key);
  // The files go with the fabric unless something else still pins them.
  for (const auto& hash : hashes) artifacts_.RemoveIfUnpinnedLocked(hash);
}

FabricEntry FabricCache::Put(const std::string& key, const std::vector<FabricFile>& files,
                             const std::string& manifest_json) {
  CheckArtifactHash(key, "fabric key");
  CheckFiles(files);
  std::lock_guard lock(artifacts_.mu_);
  SqlDb& db = *artifacts_.db_;
  SqlDb::Transaction txn(db);
  for (const FabricFile& file : files) {
    if (!artifacts_.HasLocked(file.hash)) {
      throw Error(ErrorCode::kNotFound, "fabric file " + file.name + ": artifact " + file.hash +
                                            " is not in the store (upload it first)");
    }
  }
  const int64_t now = clock_.NowMs();
  db.Run(std::string("INSERT INTO fabrics (key, manifest_json, created_ms, last_used_ms, use_seq) "
                     "VALUES (?1, ?2, ?3, ?3, ") +
             kNextUse +
             ") ON CONFLICT (key) DO UPDATE SET manifest_json = excluded.manifest_json, "
             "last_used_ms = excluded.last_used_ms, use_seq = excluded.use_seq",
         key, manifest_json, now);
  // A replaced entry's old files lose their pins and become ordinary, evictable artifacts.
  db.Run("DELETE FROM artifact_pins WHERE owner = ?", PinOwner(key));
  db.Run("DELETE FROM fabric_files WHERE key = ?", key);
  for (const FabricFile& file : files) {
    db.Run("INSERT INTO fabric_files (key, name, hash) VALUES (?, ?, ?)", key, file.name, file.hash);
    db.Run("INSERT INTO artifact_pins (hash, owner) VALUES (?, ?) ON CONFLICT DO NOTHING", file.hash, PinOwner(key));
    artifacts_.TouchLocked(file.hash);
  }
  FabricEntry entry = *FindLocked(key);
  txn.Commit();
  return entry;
}

std::optional<FabricEntry> FabricCache::Get(const std::string& key) {
  CheckArtifactHash(key, "fabric key");
  std::optional<FabricEntry> entry;
  {
    std::lock_guard lock(artifacts_.mu_);
    entry = FindLocked(key);
  }
  if (!entry) {
    ++misses_;
    return std::nullopt;
  }
  bool intact = true;
  for (const FabricFile& file : entry->files) intact = artifacts_.Verify(file.hash) && intact;

  std::lock_guard lock(artifacts_.mu_);
  SqlDb& db = *artifacts_.db_;
  SqlDb::Transaction txn(db);
  if (!intact) {
    DeleteLocked(key);
    txn.Commit();
    ++broken_;
    return std::nullopt;
  }
  db.Run(std::string("UPDATE fabrics SET last_used_ms = ?, use_seq = ") + kNextUse + " WHERE key = ?",
         clock_.NowMs(), key);
  for (const FabricFile& file : entry->files) artifacts_.TouchLocked(file.hash);
  entry = FindLocked(key);  // as it is now (a concurrent Delete or Put may have won)
  txn.Commit();
  ++(entry ? hits_ : misses_);
  return entry;
}

CacheLookups FabricCache::Lookups() const { return {hits_.load(), misses_.load(), broken_.load()}; }

std::vector<FabricEntry> FabricCache::List() {
  std::lock_guard lock(artifacts_.mu_);
  std::vector<FabricEntry> entries;
  for (auto keys = artifacts_.db_->Query("SELECT key FROM fabrics ORDER BY use_seq DESC"); keys.Step();) {
    entries.push_back(*FindLocked(keys.Text(0)));
  }
  return entries;
}

CacheTotals FabricCache::Totals() {
  std::lock_guard lock(artifacts_.mu_);
  auto query = artifacts_.db_->Query(
      "SELECT COUNT(DISTINCT f.key), COALESCE(SUM(a.size), 0) FROM fabrics f "
      "LEFT JOIN fabric_files ff ON ff.key = f.key LEFT JOIN artifacts a ON a.hash = ff.hash");
  query.Step();
  return {query.Int(0), static_cast<uint64_t>(query.Int(1))};
}

void FabricCache::Delete(const std::string& key) {
  CheckArtifactHash(key, "fabric key");
  std::lock_guard lock(artifacts_.mu_);
  SqlDb::Transaction txn(*artifacts_.db_);
  if (!FindLocked(key)) throw Error(ErrorCode::kNotFound, "fabric " + key + " is not cached");
  DeleteLocked(key);
  txn.Commit();
}

void FabricCache::SetPinned(const std::string& key, bool pinned) {
  CheckArtifactHash(key, "fabric key");
  std::lock_guard lock(artifacts_.mu_);
  artifacts_.db_->Run("UPDATE fabrics SET pinned = ? WHERE key = ?", pinned, key);
  if (artifacts_.db_->Changes() == 0) throw Error(ErrorCode::kNotFound, "fabric " + key + " is not cached");
}

void FabricCache::Pin(const std::string& key) { SetPinned(key, true); }

void FabricCache::Unpin(const std::string& key) { SetPinned(key, false); }

std::vector<std::string> FabricCache::Evict() {
  std::vector<std::string> evicted_fabrics;
  if (artifacts_.options().budget_bytes == 0) return evicted_fabrics;
  std::lock_guard lock(artifacts_.mu_);
  SqlDb& db = *artifacts_.db_;
  SqlDb::Transaction txn(db);
  std::vector<std::string> evicted_artifacts;
  artifacts_.EvictLocked(evicted_artifacts);
  while (artifacts_.TotalBytesLocked() > artifacts_.options().budget_bytes) {
    auto oldest = db.Query("SELECT key FROM fabrics WHERE pinned = 0 ORDER BY use_seq LIMIT 1");
    if (!oldest.Step()) break;
    evicted_fabrics.push_back(oldest.Text(0));
    DeleteLocked(evicted_fabrics.back());
  }
  txn.Commit();
  return evicted_fabrics;
}

}  // namespace loom::server
