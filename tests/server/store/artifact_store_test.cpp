#include "server/store/artifact_store.h"

#include <gtest/gtest.h>

#include <csignal>
#include <thread>

#include "core/util/file_io.h"
#include "core/util/sha256.h"
#include "server/store/pg_db.h"
#include "store_test_util.h"
#include "tests/server/store/postgres_server.h"

namespace loom::server {
namespace {

namespace fs = std::filesystem;

// SHA-256("hello").
const std::string kHelloHash = "2cf24dba5fb0a30e26e83b2ac5b9e29e1b161e5c1fa7425e73043362938b9824";

int CountFiles(const fs::path& dir) {
  int count = 0;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) count += entry.is_regular_file();
  return count;
}

// Temp files under DATA/tmp, not counting the stores' own directories' lock files.
int CountTempFiles(const fs::path& data_dir) {
  int count = 0;
  for (const auto& entry : fs::recursive_directory_iterator(data_dir / "tmp")) {
    count += entry.is_regular_file() && entry.path().filename() != ".lock";
  }
  return count;
}

// Every test with the catalogue in SQLite and in a real PostgreSQL
// (postgres_server.h); the files under DATA either way.
class ArtifactStoreTest : public ::testing::TestWithParam<SqlDialect> {
 protected:
  ArtifactStoreTest() : dir_(FreshDataDir()) {
    if (GetParam() == SqlDialect::kPostgres) conninfo_ = FreshPostgresDatabase();
    Reopen();
  }

  std::unique_ptr<ArtifactStore> Open(uint64_t budget_bytes = 0) {
    if (GetParam() == SqlDialect::kPostgres) {
      return std::make_unique<ArtifactStore>(dir_, std::make_unique<PgDb>(conninfo_),
                                             ArtifactStoreOptions{budget_bytes});
    }
    return std::make_unique<ArtifactStore>(dir_, ArtifactStoreOptions{budget_bytes});
  }

  void Reopen(uint64_t budget_bytes = 0) {
    store_.reset();
    store_ = Open(budget_bytes);
  }

  fs::path FileOf(const std::string& hash) const { return dir_ / "artifacts" / hash.substr(0, 2) / hash; }

  fs::path dir_;
  std::string conninfo_;  // on PostgreSQL
  std::unique_ptr<ArtifactStore> store_;
};

INSTANTIATE_TEST_SUITE_P(Stores, ArtifactStoreTest, kBothStores, StoreName);

TEST_P(ArtifactStoreTest, PutThenReadRoundTripsUnderTheContentHash) {
  EXPECT_EQ(store_->Put("hello"), kHelloHash);
  EXPECT_TRUE(fs::exists(FileOf(kHelloHash)));
  EXPECT_EQ(ReadFile(FileOf(kHelloHash)), "hello");
  EXPECT_EQ(store_->Read(kHelloHash), "hello");
  EXPECT_TRUE(store_->Has(kHelloHash));
  EXPECT_EQ(store_->Size(kHelloHash), 5u);
  EXPECT_EQ(store_->Put("hello"), kHelloHash);  // same content: stored once
  EXPECT_EQ(store_->TotalBytes(), 5u);
  EXPECT_EQ(CountFiles(dir_ / "artifacts"), 1);
}

TEST_P(ArtifactStoreTest, StreamingWriterVerifiesThenCommits) {
  ArtifactWriter writer = store_->NewWriter();
  writer.Append("hel");
  EXPECT_EQ(CountTempFiles(dir_), 1);  // the upload lives under DATA/tmp until committed
  writer.Append("lo");
  EXPECT_EQ(writer.bytes(), 5u);
  EXPECT_FALSE(store_->Has(kHelloHash));
  EXPECT_EQ(writer.Commit(kHelloHash), kHelloHash);
  EXPECT_EQ(store_->Read(kHelloHash), "hello");
  EXPECT_EQ(CountTempFiles(dir_), 0);
  EXPECT_LOOM_ERROR(writer.Append("more"), ErrorCode::kFailedPrecondition, "already committed");
}

TEST_P(ArtifactStoreTest, ChecksumMismatchStoresNothing) {
  ArtifactWriter writer = store_->NewWriter();
  writer.Append("hellO");
  EXPECT_LOOM_ERROR(writer.Commit(kHelloHash), ErrorCode::kInvalidArgument,
                    "checksum mismatch: expected " + kHelloHash);
  EXPECT_FALSE(store_->Has(kHelloHash));
  EXPECT_FALSE(store_->Has(Sha256Hex("hellO")));
  EXPECT_EQ(CountTempFiles(dir_), 0);
  EXPECT_EQ(store_->TotalBytes(), 0u);

  ArtifactWriter bad_expectation = store_->NewWriter();
  bad_expectation.Append("hello");
  EXPECT_LOOM_ERROR(bad_expectation.Commit("abc"), ErrorCode::kInvalidArgument, "expected checksum 'abc'");
  EXPECT_EQ(CountTempFiles(dir_), 0);
}

TEST_P(ArtifactStoreTest, AbandonedUploadLeavesNoTempFile) {
  {
    ArtifactWriter writer = store_->NewWriter();
    writer.Append("partial");
  }
  EXPECT_EQ(CountTempFiles(dir_), 0);
  EXPECT_EQ(store_->TotalBytes(), 0u);
}

TEST_P(ArtifactStoreTest, TempLeftoversOfACrashAreRemovedOnOpen) {
  store_->Put("kept");
  WriteFileAtomic(dir_ / "tmp" / "upload-123-0", "half an upload");
  WriteFileAtomic(dir_ / "tmp" / "nested" / "upload-123-1", "another");
  Reopen();
  EXPECT_EQ(CountTempFiles(dir_), 0);
  EXPECT_TRUE(fs::is_directory(dir_ / "tmp"));
  EXPECT_EQ(store_->Read(Sha256Hex("kept")), "kept");
}

TEST_P(ArtifactStoreTest, KillDashNineMidUploadLosesOnlyTheUpload) {
  store_.reset();
  EXPECT_EXIT(
      {
        const std::unique_ptr<ArtifactStore> server = Open();
        server->Put("committed");
        ArtifactWriter upload = server->NewWriter();
        upload.Append("half of an upl");
        std::raise(SIGKILL);
      },
      ::testing::KilledBySignal(SIGKILL), "");
  EXPECT_EQ(CountTempFiles(dir_), 1);  // what the crash left
  Reopen();
  EXPECT_EQ(CountTempFiles(dir_), 0);
  EXPECT_EQ(store_->Read(Sha256Hex("committed")), "committed");
  EXPECT_EQ(store_->TotalBytes(), 9u);
}

TEST_P(ArtifactStoreTest, CorruptFileIsDetectedRemovedAndReported) {
  store_->Put("hello");
  WriteFileAtomic(FileOf(kHelloHash), "jello");  // same size, one byte flipped
  EXPECT_LOOM_ERROR(store_->Read(kHelloHash), ErrorCode::kNotFound, "was corrupt");
  EXPECT_FALSE(fs::exists(FileOf(kHelloHash)));
  EXPECT_FALSE(store_->Has(kHelloHash));
  EXPECT_EQ(store_->Missing({kHelloHash}), std::vector<std::string>{kHelloHash});
  EXPECT_EQ(store_->TotalBytes(), 0u);
  EXPECT_LOOM_ERROR(store_->Read(kHelloHash), ErrorCode::kNotFound, "not in the store");
  EXPECT_EQ(store_->Put("hello"), kHelloHash);  // the caller re-uploads
  EXPECT_EQ(store_->Read(kHelloHash), "hello");
}

TEST_P(ArtifactStoreTest, VerifyReportsMissingAndCorruptFiles) {
  const auto a = store_->Put("aaaa");
  const auto b = store_->Put("bbbb");
  EXPECT_TRUE(store_->Verify(a));
  fs::remove(FileOf(a));
  WriteFileAtomic(FileOf(b), "bbbB");
  EXPECT_FALSE(store_->Verify(a));
  EXPECT_FALSE(store_->Verify(b));
  EXPECT_FALSE(fs::exists(FileOf(b)));
  EXPECT_EQ(store_->TotalBytes(), 0u);
}

TEST_P(ArtifactStoreTest, MissingListsAbsentHashesInOrderWithoutRepeats) {
  const auto present = store_->Put("present");
  const std::string absent1(64, '1');
  const std::string absent2(64, '2');
  EXPECT_EQ(store_->Missing({absent2, present, absent1, absent2}), (std::vector<std::string>{absent2, absent1}));
  EXPECT_TRUE(store_->Missing({present}).empty());
  EXPECT_TRUE(store_->Missing({}).empty());
}

TEST_P(ArtifactStoreTest, EvictionRemovesLeastRecentlyUsedFirst) {
  Reopen(/*budget_bytes=*/10);
  const auto a = store_->Put("aaaa");
  const auto b = store_->Put("bbbb");
  EXPECT_TRUE(store_->Evict().empty());  // 8 bytes fit
  const auto c = store_->Put("cccc");
  store_->Read(a);  // a is now more recent than b
  EXPECT_EQ(store_->Evict(), std::vector<std::string>{b});
  EXPECT_EQ(store_->TotalBytes(), 8u);
  EXPECT_FALSE(fs::exists(FileOf(b)));
  store_->Put("cccc");  // a Put of present content counts as a use
  const auto d = store_->Put("dddd");
  EXPECT_EQ(store_->Evict(), std::vector<std::string>{a});
  EXPECT_EQ(store_->Missing({a, b, c, d}), (std::vector<std::string>{a, b}));
}

TEST_P(ArtifactStoreTest, PinnedArtifactsSurviveEviction) {
  Reopen(/*budget_bytes=*/4);
  const auto a = store_->Put("aaaa");
  const auto b = store_->Put("bbbb");
  const auto c = store_->Put("cccc");
  store_->Pin(a, "job:job-1");
  store_->Pin(a, "job:job-1");  // idempotent
  store_->Pin(a, "job:job-2");
  EXPECT_EQ(store_->Evict(), (std::vector<std::string>{b, c}));
  EXPECT_TRUE(store_->Has(a));
  EXPECT_LOOM_ERROR(store_->Remove(a), ErrorCode::kFailedPrecondition, "pinned by job:job-");
  store_->Unpin(a, "job:job-1");
  store_->Put("eeee");
  EXPECT_EQ(store_->Evict(), std::vector<std::string>{Sha256Hex("eeee")});  // still pinned by job-2
  store_->UnpinAll("job:job-2");
  store_->Put("ffff");
  EXPECT_EQ(store_->Evict(), std::vector<std::string>{a});
  EXPECT_LOOM_ERROR(store_->Pin(b, "job:job-3"), ErrorCode::kNotFound, b);
  EXPECT_LOOM_ERROR(store_->Pin(a, ""), ErrorCode::kInvalidArgument, "owner");
}

TEST_P(ArtifactStoreTest, RemoveDeletesTheFile) {
  const auto a = store_->Put("aaaa");
  store_->Remove(a);
  EXPECT_FALSE(fs::exists(FileOf(a)));
  EXPECT_LOOM_ERROR(store_->Remove(a), ErrorCode::kNotFound, a);
}

TEST_P(ArtifactStoreTest, ReopenKeepsTheCatalogueAndForgetsVanishedFiles) {
  const auto a = store_->Put("aaaa");
  const auto b = store_->Put("bbbbbb");
  store_->Pin(a, "fabric:x");
  Reopen();
  EXPECT_EQ(store_->TotalBytes(), 10u);
  EXPECT_EQ(store_->Read(a), "aaaa");
  EXPECT_LOOM_ERROR(store_->Remove(a), ErrorCode::kFailedPrecondition, "fabric:x");
  store_.reset();
  fs::remove(FileOf(b));  // lost while the server was down
  Reopen();
  EXPECT_EQ(store_->TotalBytes(), 4u);
  EXPECT_FALSE(store_->Has(b));
}

TEST_P(ArtifactStoreTest, ConcurrentWritersOfSameAndDifferentContent) {
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&, t] {
      for (int i = 0; i < 20; ++i) {
        store_->Put("shared content");
        ArtifactWriter writer = store_->NewWriter();
        const std::string own = "thread " + std::to_string(t) + " item " + std::to_string(i);
        writer.Append(own);
        writer.Commit(Sha256Hex(own));
      }
    });
  }
  for (auto& thread : threads) thread.join();
  EXPECT_EQ(CountFiles(dir_ / "artifacts"), 81);
  EXPECT_EQ(CountTempFiles(dir_), 0);
  EXPECT_EQ(store_->Read(Sha256Hex("shared content")), "shared content");
}

// Servers on one PostgreSQL share DATA (a volume): a store opened beside another
// keeps the other's upload in flight, and writers in both, of the same content
// and of their own, end with every artifact once, readable through either.
TEST_P(ArtifactStoreTest, StoresSharingADataDirectoryKeepEachOthersUploadsAndWritesWhole) {
  if (GetParam() != SqlDialect::kPostgres) GTEST_SKIP() << "one store per SQLite data directory";
  ArtifactWriter in_flight = store_->NewWriter();
  in_flight.Append("half of an ");
  const std::unique_ptr<ArtifactStore> other = Open();
  in_flight.Append("upload");
  EXPECT_EQ(in_flight.Commit(Sha256Hex("half of an upload")), Sha256Hex("half of an upload"));

  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&, t] {
      ArtifactStore& store = t % 2 ? *other : *store_;
      for (int i = 0; i < 20; ++i) {
        store.Put("shared " + std::to_string(i));
        store.Put("thread " + std::to_string(t) + " item " + std::to_string(i));
      }
    });
  }
  for (auto& thread : threads) thread.join();
  EXPECT_EQ(CountFiles(dir_ / "artifacts"), 101);
  EXPECT_EQ(CountTempFiles(dir_), 0);
  uint64_t bytes = std::string("half of an upload").size();
  for (int i = 0; i < 20; ++i) {
    const std::string shared = "shared " + std::to_string(i);
    EXPECT_EQ(other->Read(Sha256Hex(shared)), shared);
    EXPECT_EQ(store_->Read(Sha256Hex(shared)), shared);
    bytes += shared.size();
    for (int t = 0; t < 4; ++t) bytes += ("thread " + std::to_string(t) + " item " + std::to_string(i)).size();
  }
  EXPECT_EQ(store_->TotalBytes(), bytes);
  EXPECT_EQ(other->TotalBytes(), bytes);
  // A pin through one keeps the artifact from the other's eviction.
  const std::unique_ptr<ArtifactStore> tight = Open(/*budget_bytes=*/1);
  store_->Pin(Sha256Hex("shared 3"), "job:x");
  tight->Evict();
  EXPECT_EQ(store_->Read(Sha256Hex("shared 3")), "shared 3");
  EXPECT_EQ(other->TotalBytes(), 8u);
}

TEST_P(ArtifactStoreTest, BadHashesAreInvalidArgumentAndLoseNothing) {
  store_->Put("hello");
  EXPECT_LOOM_ERROR(store_->Read(""), ErrorCode::kInvalidArgument, "artifact hash is empty");
  EXPECT_LOOM_ERROR(store_->Read("../../etc/passwd"), ErrorCode::kInvalidArgument, "64 lowercase hex");
  std::string upper = kHelloHash;
  upper[0] = 'C';
  EXPECT_LOOM_ERROR(store_->Has(upper), ErrorCode::kInvalidArgument, "not a SHA-256 digest");
  EXPECT_LOOM_ERROR(store_->Size(kHelloHash + "0"), ErrorCode::kInvalidArgument, "64 lowercase hex");
  EXPECT_LOOM_ERROR(store_->Missing({kHelloHash, "zz"}), ErrorCode::kInvalidArgument, "hashes[1]");
  EXPECT_LOOM_ERROR(store_->Size(std::string(64, '0')), ErrorCode::kNotFound, "not in the store");
  EXPECT_LOOM_ERROR(store_->Remove(""), ErrorCode::kInvalidArgument, "empty");
  EXPECT_EQ(store_->Read(kHelloHash), "hello");
  EXPECT_EQ(store_->TotalBytes(), 5u);
}

}  // namespace
}  // namespace loom::server
