#pragma once
// The fabric cache index: fabric key -> the fitted fabric asset (a directory of
// parameters.exr, lut.exr, manifest.json), each file an artifact in the
// ArtifactStore, plus the manifest's JSON text for GetFabric.
//
// A cached fabric pins its files ("fabric:<key>"), so artifact eviction never takes
// one file out of a fabric; FabricCache::Evict removes whole fabrics instead. The
// index lives in the artifact store's database: an entry and its pins change in
// one transaction, so a crash leaves neither a fabric without pins nor pins without
// a fabric.
//
// Get verifies every file's checksum: if one is missing or corrupt, the entry is
// evicted and Get returns nullopt, so the server schedules a new precompute rather
// than serving a broken fabric.
//
// Bad keys (not 64 lowercase hex digits, like FabricKey's output) are
// kInvalidArgument. Thread-safe.

#include <atomic>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "server/store/artifact_store.h"
#include "server/store/clock.h"

namespace loom::server {

struct FabricFile {
  std::string name;    // file name inside the asset directory, e.g. "lut.exr"
  std::string hash;    // artifact hash
  uint64_t bytes = 0;  // filled by the cache (the artifact's size)
};

struct FabricEntry {
  std::string key;
  std::vector<FabricFile> files;  // sorted by name
  std::string manifest_json;
  uint64_t total_bytes = 0;
  bool pinned = false;  // never evicted while pinned
  int64_t created_ms = 0;
  int64_t last_used_ms = 0;
};

struct CacheTotals {
  int64_t fabrics = 0;
  uint64_t bytes = 0;
};

// Get's answers since the cache was opened (this process only; for metrics).
struct CacheLookups {
  int64_t hits = 0;
  int64_t misses = 0;  // not cached
  int64_t broken = 0;  // cached, but a file was missing or corrupt: evicted
};

class FabricCache {
 public:
  // `artifacts` and `clock` must outlive the cache.
  FabricCache(ArtifactStore& artifacts, const Clock& clock);

  // Indexes (or replaces, keeping `pinned`) the fabric `key`. Every file must
  // already be in the artifact store (kNotFound naming the file otherwise); there
  // must be at least one, with names non-empty, unique and without '/'
  // (kInvalidArgument). A replaced entry's old files become ordinary artifacts.
  // Returns the entry.
  FabricEntry Put(const std::string& key, const std::vector<FabricFile>& files,
                  const std::string& manifest_json);

  // The entry, with every file verified, marked most recently used; nullopt if not
  // cached or if it was just evicted because a file is missing or corrupt.
  std::optional<FabricEntry> Get(const std::string& key);

  // Every entry, most recently used first. No verification, recency unchanged.
  std::vector<FabricEntry> List();
  // How many fabrics List would return and the sum of their total_bytes, in one query.
  CacheTotals Totals();

  CacheLookups Lookups() const;

  // Unknown key: kNotFound. Delete removes even a pinned fabric (an explicit request).
  void Delete(const std::string& key);
  void Pin(const std::string& key);
  void Unpin(const std::string& key);

  // Brings the store under its byte budget: first unpinned loose artifacts
  // (ArtifactStore::Evict: frames, meshes), then whole unpinned fabrics, least
  // recently used first. Returns the evicted fabric keys in order.
  std::vector<std::string> Evict();

 private:
  // With the store's mutex held.
  std::optional<FabricEntry> FindLocked(const std::string& key);
  void DeleteLocked(const std::string& key);
  void SetPinned(const std::string& key, bool pinned);

  ArtifactStore& artifacts_;
  const Clock& clock_;
  std::atomic<int64_t> hits_{0}, misses_{0}, broken_{0};
};

}  // namespace loom::server
