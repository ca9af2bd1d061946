#pragma once
// Content-addressed artifact files (fabric asset files, frames, uploaded meshes).
//
// An artifact is named by the SHA-256 of its bytes (64 lowercase hex digits) and
// stored at DATA/artifacts/<first two hex digits>/<hash>. Writes go to a temp file
// in this process's own directory under DATA/tmp (own_temp_dir.h) and are renamed
// into place only after the checksum is verified, so a reader never sees a partial
// artifact; temp files left by a crash are removed when a store is next opened.
// Reads verify the checksum again: a file that rotted or was tampered with is
// deleted and reported as kNotFound ("... was corrupt and has been removed"), so the
// caller treats it as missing and recomputes or re-uploads.
//
// The catalogue (size, recency, pins) lives in SQLite (DATA/cache.db, WAL) or in the
// --store PostgreSQL, not in file times. Evict() removes least recently used
// artifacts until the total fits the byte budget; an artifact with at least one pin
// is never evicted. Pins are named by an owner and idempotent, so a retried or
// repeated Pin/Unpin is harmless: the FabricCache pins its fabrics' files as
// "fabric:<key>"; the server pins a render job's meshes as "job:<id>" until the job
// ends and its frames as "result:<id>" for a while after (server/service_state.h).
//
// Several processes may share DATA (servers on one PostgreSQL catalogue, a shared
// volume): the content-addressed files make concurrent writes of one artifact
// harmless (each rename puts the same bytes in place), and a pin and an eviction or
// removal each check and change in one writer transaction, so no server evicts an
// artifact another has just pinned.
//
// Bad hashes (empty, wrong length, not lowercase hex) are kInvalidArgument.
// Thread-safe; one process per data directory on SQLite (its catalogue's lock).

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

#include "core/util/sha256.h"
#include "server/store/own_temp_dir.h"

namespace loom::server {

class SqlDb;
class ArtifactStore;

// Throws kInvalidArgument unless `hash` is 64 lowercase hex digits. `what` names
// the value in the message, e.g. "result_artifacts[2]".
void CheckArtifactHash(std::string_view hash, std::string_view what = "artifact hash");

// A streaming upload: Append chunks, then Commit. Destroying an uncommitted
// writer (or a failed Commit) removes its temp file. Not thread-safe itself;
// any number of writers may run at once. Must not outlive its store.
class ArtifactWriter {
 public:
  ArtifactWriter(ArtifactWriter&&) noexcept;
  ArtifactWriter& operator=(ArtifactWriter&&) = delete;
  ~ArtifactWriter();

  void Append(std::string_view chunk);
  uint64_t bytes() const { return bytes_; }

  // Verifies that the bytes hash to `expected_sha256` (kInvalidArgument naming both
  // hashes otherwise) and adds the artifact. Returns the hash. Call once.
  std::string Commit(std::string_view expected_sha256);

 private:
  friend class ArtifactStore;
  ArtifactWriter(ArtifactStore& store, std::filesystem::path temp_path);
  void Discard();

  ArtifactStore* store_;
  std::filesystem::path temp_path_;
  int fd_ = -1;
  Sha256 hasher_;
  uint64_t bytes_ = 0;
};

struct ArtifactStoreOptions {
  // --cache-bytes: Evict() (and FabricCache::Evict()) bring the total size of all
  // artifacts down to this, as far as pins allow. 0: no limit.
  uint64_t budget_bytes = 0;
};

class ArtifactStore {
 public:
  // Opens (creating if needed) DATA/cache.db, DATA/artifacts/ and a temp directory
  // of its own under DATA/tmp; forgets catalogue rows whose file has disappeared.
  explicit ArtifactStore(const std::filesystem::path& data_dir, ArtifactStoreOptions options = {});
  // The same with the catalogue in another database (server/store/sql_db.h; the files
  // stay under DATA).
  ArtifactStore(const std::filesystem::path& data_dir, std::unique_ptr<SqlDb> db, ArtifactStoreOptions options = {});
  ~ArtifactStore();
  ArtifactStore(const ArtifactStore&) = delete;
  ArtifactStore& operator=(const ArtifactStore&) = delete;

  const ArtifactStoreOptions& options() const { return options_; }

  // Stores `bytes` (a no-op but for recency if already present). Returns the hash.
  std::string Put(std::string_view bytes);
  ArtifactWriter NewWriter();

  // The verified bytes (the whole artifact in memory). Missing: kNotFound.
  // Corrupt: deleted, then kNotFound saying so. Marks the artifact as most recently used.
  std::string Read(std::string_view hash);
  // Read's bytes handed to `consume` a piece (1 MiB) at a time, for artifacts too
  // large to hold whole. The checksum can only be checked at the end: a corrupt
  // file is deleted and kNotFound thrown after `consume` has seen its bytes, so act
  // on them only once ReadInPieces has returned. A kNotFound the consumer throws is
  // taken for a vanished file; throw another code.
  void ReadInPieces(std::string_view hash, const std::function<void(std::string_view)>& consume);
  // Read's check without returning the bytes: false if missing or corrupt (deleted).
  bool Verify(std::string_view hash);

  // Whether the artifact is catalogued and its file exists (no checksum: see Verify).
  bool Has(std::string_view hash);
  // The hashes in `hashes` that are not Has(), in the given order, without repeats.
  std::vector<std::string> Missing(const std::vector<std::string>& hashes);
  // Size in bytes. Missing: kNotFound.
  uint64_t Size(std::string_view hash);
  // The sum of every artifact's size.
  uint64_t TotalBytes();

  // Pins are per (hash, owner); Pin on a missing artifact is kNotFound.
  void Pin(std::string_view hash, std::string_view owner);
  void Unpin(std::string_view hash, std::string_view owner);
  // Drops every pin held by `owner`.
  void UnpinAll(std::string_view owner);
  // The owners holding a pin whose name starts with `prefix`, each once, sorted.
  std::vector<std::string> PinOwners(std::string_view prefix);

  // Deletes an unpinned artifact (kFailedPrecondition if pinned, kNotFound if absent).
  void Remove(std::string_view hash);

  // Removes unpinned artifacts, least recently used first, until TotalBytes() <=
  // budget_bytes or none is left to remove. Returns the removed hashes in order.
  std::vector<std::string> Evict();

 private:
  friend class ArtifactWriter;
  friend class FabricCache;  // keeps its index in cache.db, changed with its pins in one transaction

  std::filesystem::path PathOf(std::string_view hash) const;
  // The verified bytes; a missing or corrupt file is forgotten and kNotFound thrown.
  // Takes mu_ itself, but reads and hashes without it.
  std::string Load(const std::string& hash);
  void LoadInPieces(const std::string& hash, const std::function<void(std::string_view)>& consume);

  // With mu_ held.
  void AddCommitted(const std::filesystem::path& temp_path, const std::string& hash, uint64_t size);
  bool HasLocked(const std::string& hash);
  uint64_t TotalBytesLocked();
  void TouchLocked(const std::string& hash);
  void ForgetLocked(const std::string& hash);  // drops the row and the file
  void RemoveIfUnpinnedLocked(const std::string& hash);
  void EvictLocked(std::vector<std::string>& evicted);

  const ArtifactStoreOptions options_;
  const std::filesystem::path artifacts_dir_;
  const OwnTempDir tmp_dir_;
  std::mutex mu_;
  std::unique_ptr<SqlDb> db_;
  uint64_t next_temp_ = 0;
};

}  // namespace loom::server
