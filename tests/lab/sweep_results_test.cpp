#include "lab/sweep_results.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include "core/util/error.h"
#include "core/util/file_io.h"
#include "lab/csv_table.h"

namespace loom::lab {
namespace {

class SweepResultsTest : public testing::Test {
 protected:
  void SetUp() override {
    directory_ = std::filesystem::temp_directory_path() /
                 ("loom_sweep_results_" + std::to_string(::getpid()) + "_" +
                  testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(directory_);
    path_ = directory_ / "sweep.csv";
  }
  void TearDown() override { std::filesystem::remove_all(directory_); }

  const std::vector<std::string> columns_ = {"configuration", "scene", "psnr_db"};
  std::filesystem::path directory_, path_;
};

TEST_F(SweepResultsTest, ResumesWithTheRowsAlreadyWritten) {
  {
    SweepResults results(path_, columns_);
    EXPECT_EQ(results.size(), 0u);
    results.Append({"default", "knit.flat0.mid", "14.5"});
    results.Append({"res8", "knit, quoted", "12"});
  }
  SweepResults resumed(path_, columns_);
  EXPECT_EQ(resumed.size(), 2u);
  EXPECT_TRUE(resumed.Contains("default", "knit.flat0.mid"));
  EXPECT_TRUE(resumed.Contains("res8", "knit, quoted"));
  EXPECT_FALSE(resumed.Contains("default", "knit, quoted"));
  resumed.Append({"res8", "knit.flat0.mid", "13"});

  const CsvTable table = ReadCsv(path_);
  EXPECT_EQ(table.columns, columns_);
  ASSERT_EQ(table.rows.size(), 3u);  // one header, rows appended after the old ones
  EXPECT_EQ(table.rows[1], (std::vector<std::string>{"res8", "knit, quoted", "12"}));
  EXPECT_EQ(table.rows[2][0], "res8");
}

TEST_F(SweepResultsTest, DropsALineCutOffByACrashAndMeasuresItAgain) {
  {
    SweepResults results(path_, columns_);
    results.Append({"default", "a", "1"});
  }
  std::string text = ReadFile(path_);
  WriteFileAtomic(path_, text + "default,b,1");  // no newline: the write was cut off
  SweepResults resumed(path_, columns_);
  EXPECT_TRUE(resumed.Contains("default", "a"));
  EXPECT_FALSE(resumed.Contains("default", "b"));
  resumed.Append({"default", "b", "2"});
  const CsvTable table = ReadCsv(path_);
  ASSERT_EQ(table.rows.size(), 2u);
  EXPECT_EQ(table.rows[1], (std::vector<std::string>{"default", "b", "2"}));
}

TEST_F(SweepResultsTest, RefusesACsvWithOtherColumns) {
  WriteFileAtomic(path_, "configuration,scene,rmse\nx,y,1\n");
  try {
    SweepResults results(path_, columns_);
    FAIL() << "resumed into a CSV with other columns";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kFailedPrecondition);
    EXPECT_NE(std::string(e.what()).find("columns differ"), std::string::npos) << e.what();
  }
}

TEST(CsvTable, RoundTripsQuotedFieldsAndNamesAMissingColumn) {
  const std::vector<std::string> fields = {"a,b", "say \"hi\"", "", "plain"};
  const CsvTable table = ParseCsv(CsvLine({"w", "x", "y", "z"}) + CsvLine(fields));
  ASSERT_EQ(table.rows.size(), 1u);
  EXPECT_EQ(table.rows[0], fields);
  EXPECT_EQ(table.Column("y"), 2u);
  EXPECT_THROW(table.Column("psnr_db"), Error);
  EXPECT_THROW(ParseCsv("a,b\n1,2,3\n"), Error);
}

}  // namespace
}  // namespace loom::lab
