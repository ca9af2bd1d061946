#include "server/store/fabric_cache.h"

#include <gtest/gtest.h>

#include <latch>
#include <mutex>
#include <thread>

#include "core/util/file_io.h"
#include "core/util/sha256.h"
#include "server/store/job_queue.h"
#include "server/store/pg_db.h"
#include "store_test_util.h"
#include "tests/server/store/postgres_server.h"

namespace loom::server {
namespace {

namespace fs = std::filesystem;

std::string Key(char c) { return std::string(64, c); }

// Every test with the index in SQLite and in a real PostgreSQL (postgres_server.h).
class FabricCacheTest : public ::testing::TestWithParam<SqlDialect> {
 protected:
  FabricCacheTest() : dir_(FreshDataDir()) {
    if (GetParam() == SqlDialect::kPostgres) conninfo_ = FreshPostgresDatabase();
    Reopen();
  }

  void Reopen(uint64_t budget_bytes = 0) {
    cache_.reset();
    artifacts_.reset();
    artifacts_ = GetParam() == SqlDialect::kPostgres
                     ? std::make_unique<ArtifactStore>(dir_, std::make_unique<PgDb>(conninfo_),
                                                       ArtifactStoreOptions{budget_bytes})
                     : std::make_unique<ArtifactStore>(dir_, ArtifactStoreOptions{budget_bytes});
    cache_ = std::make_unique<FabricCache>(*artifacts_, clock_);
  }

  // Uploads an asset whose three files are 10 + 10 + 7 bytes and indexes it.
  FabricEntry PutFabric(const std::string& key, char tag) {
    const std::string parameters = std::string(10, tag);
    const std::string lut = std::string(9, tag) + "L";
    const std::string manifest = "{\"" + std::string(1, tag) + "\":1}";
    return cache_->Put(key,
                       {{"parameters.exr", artifacts_->Put(parameters)},
                        {"lut.exr", artifacts_->Put(lut)},
                        {"manifest.json", artifacts_->Put(manifest)}},
                       manifest);
  }

  fs::path FileOf(const std::string& hash) const { return dir_ / "artifacts" / hash.substr(0, 2) / hash; }

  fs::path dir_;
  FakeClock clock_;
  std::string conninfo_;  // on PostgreSQL
  std::unique_ptr<ArtifactStore> artifacts_;
  std::unique_ptr<FabricCache> cache_;
};

INSTANTIATE_TEST_SUITE_P(Stores, FabricCacheTest, kBothStores, StoreName);

// Servers starting at once on a new PostgreSQL store each create the tables they
// need (artifacts, fabric index, queue): they take turns, and every one opens.
TEST_P(FabricCacheTest, ServersOpeningANewStoreAtOnceAllOpen) {
  if (GetParam() != SqlDialect::kPostgres) GTEST_SKIP() << "one server per SQLite data directory";
  const std::string fresh = FreshPostgresDatabase();
  constexpr int kServers = 6;
  std::latch start(kServers);
  std::mutex mu;
  std::vector<std::string> errors;
  std::vector<std::thread> servers;
  for (int s = 0; s < kServers; ++s) {
    servers.emplace_back([&] {
      start.arrive_and_wait();
      try {
        ArtifactStore artifacts(dir_, std::make_unique<PgDb>(fresh));
        FabricCache cache(artifacts, clock_);
        JobQueue queue(std::make_unique<PgDb>(fresh), clock_);
      } catch (const Error& error) {
        std::lock_guard lock(mu);
        errors.push_back(error.what());
      }
    });
  }
  for (auto& server : servers) server.join();
  EXPECT_TRUE(errors.empty()) << errors.size() << " failed to open, the first: " << errors.front();
}

TEST_P(FabricCacheTest, PutGetListDelete) {
  const FabricEntry put = PutFabric(Key('a'), 'a');
  ASSERT_EQ(put.files.size(), 3u);
  EXPECT_EQ(put.files[0].name, "lut.exr");  // sorted by name
  EXPECT_EQ(put.files[1].name, "manifest.json");
  EXPECT_EQ(put.files[2].name, "parameters.exr");
  EXPECT_EQ(put.files[2].hash, Sha256Hex(std::string(10, 'a')));
  EXPECT_EQ(put.files[2].bytes, 10u);
  EXPECT_EQ(put.total_bytes, 27u);
  EXPECT_EQ(put.manifest_json, "{\"a\":1}");
  EXPECT_FALSE(put.pinned);
  EXPECT_EQ(put.created_ms, clock_.NowMs());

  clock_.Advance(5000);
  const auto got = cache_->Get(Key('a'));
  ASSERT_TRUE(got.has_value());
  EXPECT_EQ(got->files.size(), 3u);
  EXPECT_EQ(got->last_used_ms, clock_.NowMs());
  EXPECT_EQ(got->created_ms, clock_.NowMs() - 5000);
  EXPECT_FALSE(cache_->Get(Key('b')).has_value());

  PutFabric(Key('b'), 'b');
  const auto listed = cache_->List();
  ASSERT_EQ(listed.size(), 2u);
  EXPECT_EQ(listed[0].key, Key('b'));  // most recently used first
  EXPECT_EQ(listed[1].key, Key('a'));
  EXPECT_EQ(cache_->Totals().fabrics, 2);
  EXPECT_EQ(cache_->Totals().bytes, listed[0].total_bytes + listed[1].total_bytes);

  cache_->Delete(Key('a'));
  EXPECT_EQ(cache_->Totals().fabrics, 1);
  EXPECT_EQ(cache_->Totals().bytes, 27u);
  EXPECT_FALSE(cache_->Get(Key('a')).has_value());
  for (const auto& file : put.files) EXPECT_FALSE(artifacts_->Has(file.hash)) << file.name;
  EXPECT_EQ(artifacts_->TotalBytes(), 27u);  // b's files
  EXPECT_LOOM_ERROR(cache_->Delete(Key('a')), ErrorCode::kNotFound, "is not cached");
}

TEST_P(FabricCacheTest, CachedFilesArePinnedAgainstArtifactEviction) {
  Reopen(/*budget_bytes=*/1);
  const FabricEntry entry = PutFabric(Key('a'), 'a');
  const auto loose = artifacts_->Put("a frame");
  EXPECT_EQ(artifacts_->Evict(), std::vector<std::string>{loose});
  EXPECT_LOOM_ERROR(artifacts_->Remove(entry.files[0].hash), ErrorCode::kFailedPrecondition, "fabric:" + Key('a'));
  EXPECT_TRUE(cache_->Get(Key('a')).has_value());
}

TEST_P(FabricCacheTest, CorruptArtifactEvictsTheWholeFabric) {
  const FabricEntry entry = PutFabric(Key('a'), 'a');
  PutFabric(Key('b'), 'b');
  WriteFileAtomic(FileOf(entry.files[0].hash), "flipped bits");
  EXPECT_FALSE(cache_->Get(Key('a')).has_value());
  ASSERT_EQ(cache_->List().size(), 1u);
  EXPECT_EQ(cache_->List()[0].key, Key('b'));
  for (const auto& file : entry.files) EXPECT_FALSE(fs::exists(FileOf(file.hash))) << file.name;
  EXPECT_FALSE(cache_->Get(Key('a')).has_value());
  ASSERT_TRUE(cache_->Get(Key('b')).has_value());
  // A recomputed asset can be cached again under the same key.
  EXPECT_EQ(PutFabric(Key('a'), 'a').files.size(), 3u);
  EXPECT_TRUE(cache_->Get(Key('a')).has_value());

  // Gets counted: the broken one, the miss after it, then two hits.
  const CacheLookups lookups = cache_->Lookups();
  EXPECT_EQ(lookups.broken, 1);
  EXPECT_EQ(lookups.misses, 1);
  EXPECT_EQ(lookups.hits, 2);
}

TEST_P(FabricCacheTest, MissingArtifactEvictsTheWholeFabric) {
  const FabricEntry entry = PutFabric(Key('a'), 'a');
  fs::remove(FileOf(entry.files[1].hash));
  EXPECT_FALSE(cache_->Get(Key('a')).has_value());
  EXPECT_TRUE(cache_->List().empty());
  EXPECT_EQ(artifacts_->TotalBytes(), 0u);
}

TEST_P(FabricCacheTest, EvictionRemovesWholeFabricsLeastRecentlyUsedFirstAndKeepsPinned) {
  Reopen(/*budget_bytes=*/54);  // two fabrics of 27 bytes
  const FabricEntry a = PutFabric(Key('a'), 'a');
  const FabricEntry b = PutFabric(Key('b'), 'b');
  const FabricEntry c = PutFabric(Key('c'), 'c');
  ASSERT_TRUE(cache_->Get(Key('a')).has_value());  // a is now the most recent
  cache_->Pin(Key('b'));                           // b is the oldest but pinned
  const auto frame = artifacts_->Put("frame");     // loose artifacts go first
  EXPECT_EQ(cache_->Evict(), std::vector<std::string>{Key('c')});
  EXPECT_FALSE(artifacts_->Has(frame));
  for (const auto& file : c.files) EXPECT_FALSE(fs::exists(FileOf(file.hash)));
  for (const auto& file : a.files) EXPECT_TRUE(fs::exists(FileOf(file.hash)));
  EXPECT_EQ(artifacts_->TotalBytes(), 54u);
  EXPECT_TRUE(cache_->List()[1].pinned);

  PutFabric(Key('d'), 'd');
  EXPECT_EQ(cache_->Evict(), std::vector<std::string>{Key('a')});  // b still pinned
  cache_->Unpin(Key('b'));
  PutFabric(Key('e'), 'e');
  EXPECT_EQ(cache_->Evict(), std::vector<std::string>{Key('b')});
  std::vector<std::string> keys;
  for (const auto& entry : cache_->List()) keys.push_back(entry.key);
  EXPECT_EQ(keys, (std::vector<std::string>{Key('e'), Key('d')}));
}

TEST_P(FabricCacheTest, PinnedFabricsAreKeptEvenOverBudget) {
  Reopen(/*budget_bytes=*/10);
  PutFabric(Key('a'), 'a');
  cache_->Pin(Key('a'));
  EXPECT_TRUE(cache_->Evict().empty());
  EXPECT_TRUE(cache_->Get(Key('a')).has_value());
  cache_->Delete(Key('a'));  // an explicit delete removes a pinned fabric
  EXPECT_TRUE(cache_->List().empty());
}

TEST_P(FabricCacheTest, ReplacingAnEntryKeepsItsPinAndReleasesOldFiles) {
  Reopen(/*budget_bytes=*/30);
  const FabricEntry old_entry = PutFabric(Key('a'), 'a');
  cache_->Pin(Key('a'));
  const FabricEntry replaced = PutFabric(Key('a'), 'z');
  EXPECT_TRUE(replaced.pinned);
  EXPECT_EQ(replaced.manifest_json, "{\"z\":1}");
  EXPECT_EQ(cache_->Evict(), std::vector<std::string>{});  // the old files were loose: evicted
  for (const auto& file : old_entry.files) EXPECT_FALSE(artifacts_->Has(file.hash));
  ASSERT_TRUE(cache_->Get(Key('a')).has_value());
  EXPECT_EQ(cache_->Get(Key('a'))->files[2].hash, Sha256Hex(std::string(10, 'z')));
}

TEST_P(FabricCacheTest, IndexSurvivesReopen) {
  PutFabric(Key('a'), 'a');
  cache_->Pin(Key('a'));
  Reopen();
  const auto entry = cache_->Get(Key('a'));
  ASSERT_TRUE(entry.has_value());
  EXPECT_TRUE(entry->pinned);
  EXPECT_EQ(entry->total_bytes, 27u);
}

TEST_P(FabricCacheTest, BadInputIsRefusedAndTheCacheIsUnchanged) {
  PutFabric(Key('a'), 'a');
  const auto hash = artifacts_->Put("x");
  EXPECT_LOOM_ERROR(cache_->Put("short", {{"f", hash}}, "{}"), ErrorCode::kInvalidArgument, "fabric key 'short'");
  EXPECT_LOOM_ERROR(cache_->Get(""), ErrorCode::kInvalidArgument, "fabric key is empty");
  EXPECT_LOOM_ERROR(cache_->Put(Key('b'), {}, "{}"), ErrorCode::kInvalidArgument, "at least one file");
  EXPECT_LOOM_ERROR(cache_->Put(Key('b'), {{"a/b", hash}}, "{}"), ErrorCode::kInvalidArgument, "files[0].name");
  EXPECT_LOOM_ERROR(cache_->Put(Key('b'), {{"f", hash}, {"f", hash}}, "{}"), ErrorCode::kInvalidArgument,
                    "appears twice");
  EXPECT_LOOM_ERROR(cache_->Put(Key('b'), {{"f", "nothex"}}, "{}"), ErrorCode::kInvalidArgument, "files[0].hash");
  EXPECT_LOOM_ERROR(cache_->Put(Key('a'), {{"f", hash}, {"lut.exr", std::string(64, '0')}}, "{}"),
                    ErrorCode::kNotFound, "fabric file lut.exr");
  EXPECT_LOOM_ERROR(cache_->Pin(Key('c')), ErrorCode::kNotFound, "is not cached");
  EXPECT_LOOM_ERROR(cache_->Unpin(Key('c')), ErrorCode::kNotFound, "is not cached");

  const auto entries = cache_->List();
  ASSERT_EQ(entries.size(), 1u);
  EXPECT_EQ(entries[0].files.size(), 3u);  // the failed replacement of 'a' changed nothing
  EXPECT_EQ(entries[0].manifest_json, "{\"a\":1}");
  EXPECT_TRUE(cache_->Get(Key('a')).has_value());
}

}  // namespace
}  // namespace loom::server
