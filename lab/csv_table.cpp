#include "lab/csv_table.h"

#include "core/util/error.h"
#include "core/util/file_io.h"

namespace loom::lab {

size_t CsvTable::Column(const std::string& name) const {
  for (size_t i = 0; i < columns.size(); ++i) {
    if (columns[i] == name) return i;
  }
  std::string known;
  for (const std::string& column : columns) known += (known.empty() ? "" : ", ") + column;
  throw Error(ErrorCode::kInvalidArgument, "CSV has no column '" + name + "' (columns: " + known + ")");
}

std::string CsvLine(const std::vector<std::string>& fields) {
  std::string line;
  for (size_t i = 0; i < fields.size(); ++i) {
    if (i > 0) line += ',';
    const std::string& field = fields[i];
    if (field.find_first_of(",\"\n\r") == std::string::npos) {
      line += field;
      continue;
    }
    line += '"';
    for (const char c : field) line += c == '"' ? std::string("\"\"") : std::string(1, c);
    line += '"';
  }
  return line + '\n';
}

CsvTable ParseCsv(const std::string& text, size_t* complete_bytes) {
  CsvTable table;
  std::vector<std::string> fields;
  std::string field;
  bool quoted = false;
  size_t line_number = 1;
  size_t complete = 0;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (quoted) {
      if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') {
        field += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        field += c;
      }
      continue;
    }
    if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      fields.push_back(std::move(field));
      field.clear();
    } else if (c == '\n') {
      fields.push_back(std::move(field));
      field.clear();
      if (!fields.empty() && fields.back().ends_with('\r')) fields.back().pop_back();
      if (table.columns.empty()) {
        table.columns = std::move(fields);
      } else if (fields.size() != table.columns.size()) {
        throw Error(ErrorCode::kInvalidArgument, "CSV line " + std::to_string(line_number) + " has " +
                                                     std::to_string(fields.size()) + " fields, the header " +
                                                     std::to_string(table.columns.size()));
      } else {
        table.rows.push_back(std::move(fields));
      }
      fields.clear();
      complete = i + 1;
      ++line_number;
    } else {
      field += c;
    }
  }
  if (complete_bytes != nullptr) *complete_bytes = complete;
  return table;
}

CsvTable ReadCsv(const std::filesystem::path& path) {
  try {
    return ParseCsv(ReadFile(path));
  } catch (const Error& e) {
    if (e.code() != ErrorCode::kInvalidArgument) throw;
    throw Error(e.code(), path.string() + ": " + e.what());
  }
}

CsvTable ReadCsvs(const std::vector<std::filesystem::path>& paths) {
  CsvTable all;
  for (const std::filesystem::path& path : paths) {
    CsvTable table = ReadCsv(path);
    if (all.columns.empty()) {
      all.columns = std::move(table.columns);
    } else if (table.columns != all.columns) {
      throw Error(ErrorCode::kInvalidArgument,
                  path.string() + ": its columns differ from " + paths.front().string() + "'s");
    }
    for (auto& row : table.rows) all.rows.push_back(std::move(row));
  }
  return all;
}

}  // namespace loom::lab
