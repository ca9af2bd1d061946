#include "server/store/artifact_store.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <optional>
#include <set>
#include <utility>

#include "core/util/error.h"
#include "core/util/file_io.h"
#include "server/store/sqlite_db.h"

namespace loom::server {
namespace {

// In both SQLite's and PostgreSQL's dialect.
constexpr const char* kSchema = R"sql(
CREATE TABLE IF NOT EXISTS artifacts (
  hash TEXT PRIMARY KEY,
  size BIGINT NOT NULL,
  use_seq BIGINT NOT NULL);  -- larger: used more recently
CREATE INDEX IF NOT EXISTS artifacts_by_use ON artifacts(use_seq);
CREATE TABLE IF NOT EXISTS artifact_pins (
  hash TEXT NOT NULL,
  owner TEXT NOT NULL,
  PRIMARY KEY (hash, owner));
CREATE INDEX IF NOT EXISTS artifact_pins_by_owner ON artifact_pins(owner);
)sql";

constexpr const char* kNextUse = "(SELECT COALESCE(MAX(use_seq), 0) + 1 FROM artifacts)";

[[noreturn]] void ThrowSystem(ErrorCode code, const std::string& what) {
  throw Error(code, what + ": " + std::strerror(errno));
}

// Filesystem failures (disk full, permissions) as loom::Error, like every other failure.
void CheckFilesystem(const std::error_code& ec, const std::string& what) {
  if (ec) throw Error(ErrorCode::kUnavailable, what + ": " + ec.message());
}

}  // namespace

void CheckArtifactHash(std::string_view hash, std::string_view what) {
  if (hash.empty()) throw Error(ErrorCode::kInvalidArgument, std::string(what) + " is empty");
  const bool valid = hash.size() == 64 && std::all_of(hash.begin(), hash.end(), [](char c) {
                       return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f');
                     });
  if (!valid) {
    const std::string shown = hash.size() > 80 ? std::string(hash.substr(0, 80)) + "..." : std::string(hash);
    throw Error(ErrorCode::kInvalidArgument,
                std::string(what) + " '" + shown + "' is not a SHA-256 digest (64 lowercase hex digits)");
  }
}

// --- ArtifactWriter -------------------------------------------------------------------

ArtifactWriter::ArtifactWriter(ArtifactStore& store, std::filesystem::path temp_path)
    : store_(&store), temp_path_(std::move(temp_path)) {
  fd_ = ::open(temp_path_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd_ < 0) ThrowSystem(ErrorCode::kUnavailable, "cannot create " + temp_path_.string());
}

ArtifactWriter::ArtifactWriter(ArtifactWriter&& other) noexcept
    : store_(other.store_),
      temp_path_(std::move(other.temp_path_)),
      fd_(std::exchange(other.fd_, -1)),
      hasher_(std::move(other.hasher_)),
      bytes_(other.bytes_) {
  other.temp_path_.clear();
}

ArtifactWriter::~ArtifactWriter() { Discard(); }

void ArtifactWriter::Discard() {
  if (fd_ >= 0) ::close(std::exchange(fd_, -1));
  if (!temp_path_.empty()) {
    std::error_code ignored;
    std::filesystem::remove(temp_path_, ignored);
    temp_path_.clear();
  }
}

void ArtifactWriter::Append(std::string_view chunk) {
  if (fd_ < 0) throw Error(ErrorCode::kFailedPrecondition, "artifact writer already committed or discarded");
  hasher_.Update(chunk);
  for (size_t written = 0; written < chunk.size();) {
    const ssize_t n = ::write(fd_, chunk.data() + written, chunk.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const std::string what = "cannot write " + temp_path_.string();
      Discard();
      ThrowSystem(ErrorCode::kUnavailable, what);
    }
    written += static_cast<size_t>(n);
  }
  bytes_ += chunk.size();
}

std::string ArtifactWriter::Commit(std::string_view expected_sha256) {
  if (fd_ < 0) throw Error(ErrorCode::kFailedPrecondition, "artifact writer already committed or discarded");
  try {
    CheckArtifactHash(expected_sha256, "expected checksum");
    if (::close(std::exchange(fd_, -1)) != 0) ThrowSystem(ErrorCode::kUnavailable, "cannot write " + temp_path_.string());
    const std::string actual = hasher_.FinishHex();
    if (actual != expected_sha256) {
      throw Error(ErrorCode::kInvalidArgument, "upload checksum mismatch: expected " + std::string(expected_sha256) +
                                                   ", the " + std::to_string(bytes_) + " bytes received hash to " +
                                                   actual);
    }
    store_->AddCommitted(temp_path_, actual, bytes_);
    temp_path_.clear();  // renamed into the store (or dropped as a duplicate)
    return actual;
  } catch (...) {
    Discard();
    throw;
  }
}

// --- ArtifactStore --------------------------------------------------------------------

ArtifactStore::ArtifactStore(const std::filesystem::path& data_dir, ArtifactStoreOptions options)
    : ArtifactStore(data_dir, std::make_unique<SqliteDb>(data_dir / "cache.db"), options) {}

ArtifactStore::ArtifactStore(const std::filesystem::path& data_dir, std::unique_ptr<SqlDb> db,
                             ArtifactStoreOptions options)
    : options_(options), artifacts_dir_(data_dir / "artifacts"), tmp_dir_(data_dir / "tmp"), db_(std::move(db)) {
  std::error_code ec;
  std::filesystem::create_directories(artifacts_dir_, ec);
  CheckFilesystem(ec, "cannot create " + artifacts_dir_.string());
  CreateSchema(*db_, kSchema);
  std::vector<std::string> vanished;
  for (auto rows = db_->Query("SELECT hash FROM artifacts"); rows.Step();) {
    std::error_code missing;
    if (!std::filesystem::exists(PathOf(rows.Text(0)), missing)) vanished.push_back(rows.Text(0));
  }
  for (const auto& hash : vanished) ForgetLocked(hash);
}

ArtifactStore::~ArtifactStore() = default;

std::filesystem::path ArtifactStore::PathOf(std::string_view hash) const {
  return artifacts_dir_ / hash.substr(0, 2) / hash;
}

ArtifactWriter ArtifactStore::NewWriter() {
  uint64_t n = 0;
  {
    std::lock_guard lock(mu_);
    n = next_temp_++;
  }
  return ArtifactWriter(*this, tmp_dir_.path() / ("upload-" + std::to_string(n)));
}

std::string ArtifactStore::Put(std::string_view bytes) {
  const std::string hash = Sha256Hex(bytes);
  {
    std::lock_guard lock(mu_);
    if (HasLocked(hash)) {
      TouchLocked(hash);
      return hash;
    }
  }
  ArtifactWriter writer = NewWriter();
  writer.Append(bytes);
  return writer.Commit(hash);
}

void ArtifactStore::AddCommitted(const std::filesystem::path& temp_path, const std::string& hash, uint64_t size) {
  std::lock_guard lock(mu_);
  std::error_code ec;
  if (HasLocked(hash)) {
    std::filesystem::remove(temp_path, ec);
    TouchLocked(hash);
    return;
  }
  // Row first, rename before the commit: both happen under mu_, and a crash in
  // between leaves at worst a row without a file, which Has() and Open forget.
  SqlDb::Transaction txn(*db_);
  db_->Run(std::string("INSERT INTO artifacts (hash, size, use_seq) VALUES (?, ?, ") + kNextUse +
               ") ON CONFLICT (hash) DO UPDATE SET size = excluded.size, use_seq = excluded.use_seq",
           hash, size);
  const auto path = PathOf(hash);
  std::filesystem::create_directories(path.parent_path(), ec);
  CheckFilesystem(ec, "cannot create " + path.parent_path().string());
  std::filesystem::rename(temp_path, path, ec);
  CheckFilesystem(ec, "cannot move " + temp_path.string() + " to " + path.string());
  txn.Commit();
}

bool ArtifactStore::HasLocked(const std::string& hash) {
  if (!db_->Query("SELECT 1 FROM artifacts WHERE hash = ?", hash).Step()) return false;
  std::error_code ec;
  if (std::filesystem::exists(PathOf(hash), ec)) return true;
  ForgetLocked(hash);
  return false;
}

void ArtifactStore::TouchLocked(const std::string& hash) {
  db_->Run(std::string("UPDATE artifacts SET use_seq = ") + kNextUse + " WHERE hash = ?", hash);
}

void ArtifactStore::ForgetLocked(const std::string& hash) {
  db_->Run("DELETE FROM artifacts WHERE hash = ?", hash);
  std::error_code ignored;
  std::filesystem::remove(PathOf(hash), ignored);
}

void ArtifactStore::RemoveIfUnpinnedLocked(const std::string& hash) {
  if (!db_->Query("SELECT 1 FROM artifact_pins WHERE hash = ?", hash).Step()) ForgetLocked(hash);
}

void ArtifactStore::LoadInPieces(const std::string& hash, const std::function<void(std::string_view)>& consume) {
  {
    std::lock_guard lock(mu_);
    if (!HasLocked(hash)) throw Error(ErrorCode::kNotFound, "artifact " + hash + " is not in the store");
  }
  // Read and hash outside the lock: other requests go on meanwhile.
  Sha256 hasher;
  uint64_t size = 0;
  bool readable = true;
  try {
    ReadFileInPieces(PathOf(hash), [&](std::string_view piece) {
      hasher.Update(piece);
      size += piece.size();
      consume(piece);
    });
  } catch (const Error& error) {
    if (error.code() != ErrorCode::kNotFound) throw;  // the consumer's own error
    readable = false;                                 // removed (evicted) since the check
  }
  const std::string actual = readable ? hasher.FinishHex() : std::string();
  if (readable && actual == hash) return;
  std::lock_guard lock(mu_);
  ForgetLocked(hash);
  if (!readable) throw Error(ErrorCode::kNotFound, "artifact " + hash + " is not in the store");
  throw Error(ErrorCode::kNotFound, "artifact " + hash + " was corrupt (its " + std::to_string(size) +
                                        " bytes hash to " + actual + ") and has been removed");
}

std::string ArtifactStore::Load(const std::string& hash) {
  std::string bytes;
  LoadInPieces(hash, [&bytes](std::string_view piece) { bytes.append(piece); });
  return bytes;
}

void ArtifactStore::ReadInPieces(std::string_view hash, const std::function<void(std::string_view)>& consume) {
  CheckArtifactHash(hash);
  LoadInPieces(std::string(hash), consume);
  std::lock_guard lock(mu_);
  TouchLocked(std::string(hash));
}

std::string ArtifactStore::Read(std::string_view hash) {
  CheckArtifactHash(hash);
  std::string bytes = Load(std::string(hash));
  std::lock_guard lock(mu_);
  TouchLocked(std::string(hash));
  return bytes;
}

bool ArtifactStore::Verify(std::string_view hash) {
  CheckArtifactHash(hash);
  try {
    Load(std::string(hash));
    return true;
  } catch (const Error& error) {
    if (error.code() != ErrorCode::kNotFound) throw;
    return false;
  }
}

bool ArtifactStore::Has(std::string_view hash) {
  CheckArtifactHash(hash);
  std::lock_guard lock(mu_);
  return HasLocked(std::string(hash));
}

std::vector<std::string> ArtifactStore::Missing(const std::vector<std::string>& hashes) {
  for (size_t i = 0; i < hashes.size(); ++i) CheckArtifactHash(hashes[i], "hashes[" + std::to_string(i) + "]");
  std::lock_guard lock(mu_);
  std::vector<std::string> missing;
  std::set<std::string> seen;
  for (const auto& hash : hashes) {
    if (seen.insert(hash).second && !HasLocked(hash)) missing.push_back(hash);
  }
  return missing;
}

uint64_t ArtifactStore::Size(std::string_view hash) {
  CheckArtifactHash(hash);
  std::lock_guard lock(mu_);
  const std::string key(hash);
  if (!HasLocked(key)) throw Error(ErrorCode::kNotFound, "artifact " + key + " is not in the store");
  auto query = db_->Query("SELECT size FROM artifacts WHERE hash = ?", key);
  query.Step();
  return static_cast<uint64_t>(query.Int(0));
}

uint64_t ArtifactStore::TotalBytes() {
  std::lock_guard lock(mu_);
  return TotalBytesLocked();
}

uint64_t ArtifactStore::TotalBytesLocked() {
  auto query = db_->Query("SELECT COALESCE(SUM(size), 0) FROM artifacts");
  query.Step();
  return static_cast<uint64_t>(query.Int(0));
}

void ArtifactStore::Pin(std::string_view hash, std::string_view owner) {
  CheckArtifactHash(hash);
  if (owner.empty()) throw Error(ErrorCode::kInvalidArgument, "pin owner is empty");
  std::lock_guard lock(mu_);
  const std::string key(hash);
  SqlDb::Transaction txn(*db_);  // no other server evicts it between the check and the pin
  if (!HasLocked(key)) throw Error(ErrorCode::kNotFound, "artifact " + key + " is not in the store");
  db_->Run("INSERT INTO artifact_pins (hash, owner) VALUES (?, ?) ON CONFLICT DO NOTHING", key, owner);
  txn.Commit();
}

void ArtifactStore::Unpin(std::string_view hash, std::string_view owner) {
  CheckArtifactHash(hash);
  std::lock_guard lock(mu_);
  db_->Run("DELETE FROM artifact_pins WHERE hash = ? AND owner = ?", hash, owner);
}

void ArtifactStore::UnpinAll(std::string_view owner) {
  std::lock_guard lock(mu_);
  db_->Run("DELETE FROM artifact_pins WHERE owner = ?", owner);
}

std::vector<std::string> ArtifactStore::PinOwners(std::string_view prefix) {
  std::lock_guard lock(mu_);
  std::vector<std::string> owners;
  for (auto query = db_->Query("SELECT DISTINCT owner FROM artifact_pins WHERE substr(owner, 1, ?) = ? ORDER BY owner",
                               static_cast<int64_t>(prefix.size()), prefix);
       query.Step();) {
    owners.push_back(query.Text(0));
  }
  return owners;
}

void ArtifactStore::Remove(std::string_view hash) {
  CheckArtifactHash(hash);
  std::lock_guard lock(mu_);
  const std::string key(hash);
  SqlDb::Transaction txn(*db_);  // no other server pins it between the check and the removal
  if (auto pin = db_->Query("SELECT owner FROM artifact_pins WHERE hash = ? LIMIT 1", key); pin.Step()) {
    throw Error(ErrorCode::kFailedPrecondition, "artifact " + key + " is pinned by " + pin.Text(0));
  }
  if (!HasLocked(key)) throw Error(ErrorCode::kNotFound, "artifact " + key + " is not in the store");
  ForgetLocked(key);
  txn.Commit();
}

std::vector<std::string> ArtifactStore::Evict() {
  std::lock_guard lock(mu_);
  std::vector<std::string> evicted;
  SqlDb::Transaction txn(*db_);  // no other server pins one between the choice and the removal
  EvictLocked(evicted);
  txn.Commit();
  return evicted;
}

void ArtifactStore::EvictLocked(std::vector<std::string>& evicted) {
  if (options_.budget_bytes == 0) return;
  uint64_t total = TotalBytesLocked();
  std::vector<std::pair<std::string, uint64_t>> candidates;
  for (auto query = db_->Query(
           "SELECT hash, size FROM artifacts WHERE hash NOT IN (SELECT hash FROM artifact_pins) ORDER BY use_seq");
       total > options_.budget_bytes && query.Step();) {
    candidates.emplace_back(query.Text(0), static_cast<uint64_t>(query.Int(1)));
    total -= std::min(total, candidates.back().second);
  }
  for (const auto& [hash, size] : candidates) {
    ForgetLocked(hash);
    evicted.push_back(hash);
  }
}

}  // namespace loom::server
