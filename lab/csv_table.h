#pragma once
// The sweep's CSV (RFC 4180 subset: comma separated, a field quoted when it holds a
// comma, quote or newline, quotes doubled), read back by `chart` and by the sweep
// itself when it resumes.

#include <filesystem>
#include <string>
#include <vector>

namespace loom::lab {

struct CsvTable {
  std::vector<std::string> columns;
  std::vector<std::vector<std::string>> rows;  // each as wide as `columns`

  // The index of `name`; Error(kInvalidArgument) naming the file's columns if absent.
  size_t Column(const std::string& name) const;
};

// One line, ending in '\n'.
std::string CsvLine(const std::vector<std::string>& fields);

// Parses complete lines only: text after the last '\n' (a line cut off by a crash)
// is not part of the table; `complete_bytes` receives the length of the part that
// was. Error(kInvalidArgument) naming the line if a row's width differs from the
// header's.
CsvTable ParseCsv(const std::string& text, size_t* complete_bytes = nullptr);
CsvTable ReadCsv(const std::filesystem::path& path);
// The rows of several CSVs with the same columns, in order (a sweep and its
// repeats under other seeds); Error(kInvalidArgument) naming the file whose columns
// differ from the first's.
CsvTable ReadCsvs(const std::vector<std::filesystem::path>& paths);

}  // namespace loom::lab
