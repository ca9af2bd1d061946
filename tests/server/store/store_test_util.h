#pragma once
// Shared by the store tests: a fresh data directory per test, and an assertion on
// a loom::Error's code and message.

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "core/util/error.h"
#include "server/store/sql_db.h"

namespace loom::server {

// An empty directory named after the running test.
inline std::filesystem::path FreshDataDir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const auto dir = std::filesystem::path(::testing::TempDir()) / "loom_store_test" /
                   (std::string(info->test_suite_name()) + "." + info->name());
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// The tests that run on both databases: SQLite, and PostgreSQL (postgres_server.h).
// INSTANTIATE_TEST_SUITE_P(Stores, Suite, kBothStores, StoreName) names them
// Stores/Suite.Test/sqlite and …/postgresql.
inline const auto kBothStores = ::testing::Values(SqlDialect::kSqlite, SqlDialect::kPostgres);
inline std::string StoreName(const ::testing::TestParamInfo<SqlDialect>& info) {
  return info.param == SqlDialect::kPostgres ? "postgresql" : "sqlite";
}

// Runs `statement`, expecting a loom::Error with `code` whose message contains `text`.
#define EXPECT_LOOM_ERROR(statement, expected_code, text)                                       \
  do {                                                                                          \
    try {                                                                                       \
      statement;                                                                                \
      ADD_FAILURE() << "expected " << ::loom::ErrorCodeName(expected_code) << " from " #statement; \
    } catch (const ::loom::Error& error) {                                                      \
      EXPECT_EQ(error.code(), expected_code) << error.what();                                   \
      EXPECT_NE(std::string(error.what()).find(text), std::string::npos) << error.what();       \
    }                                                                                           \
  } while (0)

}  // namespace loom::server
