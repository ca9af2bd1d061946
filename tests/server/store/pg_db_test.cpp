// server/store/pg_db.h on a real PostgreSQL (tests/server/store/postgres_server.h):
// placeholders and every bound type round-trip, transactions roll back unless
// committed, writers take turns across connections, errors name the statement and
// leave the connection usable, rows leased with FOR UPDATE SKIP LOCKED go to one
// connection each, and a server that went away is kUnavailable until it is back
// (until the transaction it was lost in ended).

#include "server/store/pg_db.h"

#include <gtest/gtest.h>

#include <memory>

#include "store_test_util.h"
#include "tests/server/store/postgres_server.h"

namespace loom::server {
namespace {

class PgDbTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { server_ = new PostgresServer(); }
  static void TearDownTestSuite() {
    delete server_;
    server_ = nullptr;
  }
  // A database of its own per test.
  void SetUp() override {
    database_ = "t_" + std::to_string(++databases_);
    server_->CreateDatabase(database_);
  }
  std::unique_ptr<PgDb> Connect() const { return std::make_unique<PgDb>(server_->ConnInfo(database_)); }

  static PostgresServer* server_;
  static int databases_;
  std::string database_;
};

PostgresServer* PgDbTest::server_ = nullptr;
int PgDbTest::databases_ = 0;

TEST(PgPlaceholders, AreNumberedInOrderAndLeftAloneInLiterals) {
  EXPECT_EQ(ToPgPlaceholders("SELECT ? + ?, ?"), "SELECT $1 + $2, $3");
  EXPECT_EQ(ToPgPlaceholders("WHERE a = ?2 AND b = ?1 OR c = ?1"), "WHERE a = $2 AND b = $1 OR c = $1");
  EXPECT_EQ(ToPgPlaceholders("SELECT '?', \"a?\", ? FROM t WHERE x = 'it''s ?'"),
            "SELECT '?', \"a?\", $1 FROM t WHERE x = 'it''s ?'");
}

TEST_F(PgDbTest, EveryBoundTypeRoundTrips) {
  auto db = Connect();
  EXPECT_EQ(db->dialect(), SqlDialect::kPostgres);
  db->Exec("CREATE TABLE t (id BIGSERIAL PRIMARY KEY, i BIGINT, d DOUBLE PRECISION, s TEXT, b BYTEA, flag BOOLEAN)");
  const std::string bytes("\0\x01\xff payload \0", 13);
  const std::string text = "it's a ? and a \"quote\", ünïcode";
  auto inserted = db->Query("INSERT INTO t (i, d, s, b, flag) VALUES (?, ?, ?, ?, ?) RETURNING id",
                            int64_t{-9'007'199'254'740'993}, 0.1, text, Blob{bytes}, true);
  ASSERT_TRUE(inserted.Step());
  EXPECT_EQ(inserted.Int(0), 1);
  EXPECT_EQ(db->Changes(), 1);
  auto row = db->Query("SELECT i, d, s, b, flag, NULL FROM t WHERE id = ?1 AND s = ?2", 1, text);
  ASSERT_TRUE(row.Step());
  EXPECT_EQ(row.Int(0), -9'007'199'254'740'993);
  EXPECT_EQ(row.Double(1), 0.1);  // 17 digits: exact
  EXPECT_EQ(row.Text(2), text);
  EXPECT_EQ(row.Text(3), bytes);
  EXPECT_EQ(row.Int(4), 1);
  EXPECT_EQ(row.Text(5), "");  // NULL
  EXPECT_FALSE(row.Step());
  db->Run("UPDATE t SET i = i + 1");
  EXPECT_EQ(db->Changes(), 1);
  db->Run("DELETE FROM t WHERE id = ?", 2);
  EXPECT_EQ(db->Changes(), 0);
}

TEST_F(PgDbTest, ATransactionRollsBackUnlessCommitted) {
  auto db = Connect();
  db->Exec("CREATE TABLE t (v INT)");
  {
    SqlDb::Transaction txn(*db);
    db->Run("INSERT INTO t VALUES (1)");
  }
  {
    SqlDb::Transaction txn(*db);
    db->Run("INSERT INTO t VALUES (2)");
    txn.Commit();
  }
  auto rows = db->Query("SELECT v FROM t");
  ASSERT_TRUE(rows.Step());
  EXPECT_EQ(rows.Int(0), 2);
  EXPECT_FALSE(rows.Step());
}

TEST_F(PgDbTest, AFailedStatementNamesItselfAndTheConnectionGoesOn) {
  auto db = Connect();
  db->Exec("CREATE TABLE t (k TEXT PRIMARY KEY)");
  db->Run("INSERT INTO t VALUES (?)", "a");
  EXPECT_LOOM_ERROR(db->Run("INSERT INTO t VALUES (?)", "a"), ErrorCode::kInternal, "INSERT INTO t VALUES (?)");
  EXPECT_LOOM_ERROR(db->Query("SELEC 1"), ErrorCode::kInternal, "syntax error");
  {
    SqlDb::Transaction txn(*db);
    EXPECT_LOOM_ERROR(db->Query("SELECT nope FROM t"), ErrorCode::kInternal, "nope");
  }  // rolled back: the aborted transaction does not outlive it
  auto count = db->Query("SELECT COUNT(*) FROM t");
  ASSERT_TRUE(count.Step());
  EXPECT_EQ(count.Int(0), 1);
}

TEST_F(PgDbTest, SkipLockedGivesEachRowToOneConnection) {
  auto first = Connect();
  auto second = Connect();
  first->Exec("CREATE TABLE queue (seq BIGSERIAL PRIMARY KEY, state INT NOT NULL)");
  for (int i = 0; i < 3; ++i) first->Run("INSERT INTO queue (state) VALUES (0)");
  const char* lease = "SELECT seq FROM queue WHERE state = 0 ORDER BY seq LIMIT 1 FOR UPDATE SKIP LOCKED";
  first->Exec("BEGIN");
  auto a_row = first->Query(lease);
  ASSERT_TRUE(a_row.Step());
  second->Exec("BEGIN");
  auto b_row = second->Query(lease);
  ASSERT_TRUE(b_row.Step());
  EXPECT_EQ(a_row.Int(0), 1);
  EXPECT_EQ(b_row.Int(0), 2);  // not 1: locked by the first, skipped
  // Without SKIP LOCKED the second would wait for the first; with NOWAIT it is
  // refused at once, as a failure worth retrying.
  auto third = Connect();
  third->Exec("BEGIN");
  EXPECT_LOOM_ERROR(third->Query("SELECT seq FROM queue WHERE seq = 1 FOR UPDATE NOWAIT"), ErrorCode::kUnavailable,
                    "could not obtain lock");
}

TEST_F(PgDbTest, WriterTransactionsTakeTurnsAcrossConnections) {
  auto first = Connect();
  auto second = Connect();
  first->Exec("CREATE TABLE t (v INT)");
  SqlDb::Transaction writing(*first);
  // The second writer waits for the store's lock; with a short lock timeout it gives
  // up instead, a failure worth retrying. A reader does not wait.
  second->Exec("SET lock_timeout = '50ms'");
  EXPECT_LOOM_ERROR(SqlDb::Transaction waiting(*second), ErrorCode::kUnavailable, "lock timeout");
  auto count = second->Query("SELECT COUNT(*) FROM t");
  ASSERT_TRUE(count.Step());
  writing.Commit();
  SqlDb::Transaction next(*second);
  next.Commit();
}

TEST_F(PgDbTest, AServerThatWentAwayIsUnavailableUntilItIsBack) {
  auto db = Connect();
  db->Exec("CREATE TABLE t (v INT)");
  server_->Kill();
  EXPECT_LOOM_ERROR(db->Run("INSERT INTO t VALUES (1)"), ErrorCode::kUnavailable, "PostgreSQL at ");
  EXPECT_LOOM_ERROR(PgDb(server_->ConnInfo(database_)), ErrorCode::kUnavailable, "cannot connect");
  server_->Restart();
  // The same PgDb reconnects on its next statement.
  db->Run("INSERT INTO t VALUES (1)");
  EXPECT_EQ(db->Changes(), 1);
}

// A transaction whose connection was lost is lost: the statements after it, its
// commit included, are kUnavailable, never run on a new connection as if nothing
// happened; the next transaction reconnects.
TEST_F(PgDbTest, AConnectionLostInsideATransactionFailsItToTheEnd) {
  auto db = Connect();
  db->Exec("CREATE TABLE t (v INT)");
  {
    SqlDb::Transaction txn(*db);
    db->Run("INSERT INTO t VALUES (1)");
    server_->Kill();
    EXPECT_LOOM_ERROR(db->Run("INSERT INTO t VALUES (2)"), ErrorCode::kUnavailable, "PostgreSQL at ");
    server_->Restart();
    EXPECT_LOOM_ERROR(db->Run("INSERT INTO t VALUES (3)"), ErrorCode::kUnavailable, "lost inside a transaction");
    EXPECT_LOOM_ERROR(txn.Commit(), ErrorCode::kUnavailable, "lost inside a transaction");
  }
  SqlDb::Transaction again(*db);
  db->Run("INSERT INTO t VALUES (4)");
  again.Commit();
  auto rows = db->Query("SELECT COUNT(*), MAX(v) FROM t");
  rows.Step();
  EXPECT_EQ(rows.Int(0), 1);
  EXPECT_EQ(rows.Int(1), 4);
}

TEST(PgDbConnect, ABadConnectionStringIsUnavailableWithoutThePassword) {
  try {
    PgDb db("host=/nonexistent port=1 user=loom password=s3cret dbname=x connect_timeout=1");
    FAIL() << "connected";
  } catch (const Error& error) {
    EXPECT_EQ(error.code(), ErrorCode::kUnavailable);
    EXPECT_EQ(std::string(error.what()).find("s3cret"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("/nonexistent"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace loom::server
