#include "colmap_plugins/nav/csv_table.h"

#include <algorithm>
#include <charconv>
#include <cmath>

#include "common/util/error.h"
#include "common/util/file.h"

namespace uw {
namespace {

std::string Trim(const std::string& text) {
  const size_t first = text.find_first_not_of(" \t");
  if (first == std::string::npos) return "";
  return text.substr(first, text.find_last_not_of(" \t") - first + 1);
}

std::vector<std::string> SplitFields(const std::string& line) {
  std::vector<std::string> fields;
  size_t start = 0;
  while (true) {
    const size_t comma = line.find(',', start);
    fields.push_back(Trim(line.substr(start, comma - start)));
    if (comma == std::string::npos) return fields;
    start = comma + 1;
  }
}

std::string Join(const std::vector<std::string>& names) {
  std::string joined;
  for (const std::string& name : names) {
    joined += (joined.empty() ? "" : ",") + name;
  }
  return joined;
}

// What is wrong with a header, or "" when it is fine.
std::string HeaderProblem(const std::vector<std::string>& header,
                          const std::vector<std::string>& columns,
                          const std::vector<std::string>& required) {
  for (size_t i = 0; i < header.size(); ++i) {
    if (std::find(columns.begin(), columns.end(), header[i]) == columns.end()) {
      return "unknown column '" + header[i] + "'";
    }
    if (std::find(header.begin(), header.begin() + i, header[i]) !=
        header.begin() + i) {
      return "column '" + header[i] + "' appears twice";
    }
  }
  for (const std::string& name : required) {
    if (std::find(header.begin(), header.end(), name) == header.end()) {
      return "no column '" + name + "'";
    }
  }
  return "";
}

std::string ExpectedHeader(const std::vector<std::string>& columns,
                           const std::vector<std::string>& required) {
  std::string text = "'" + Join(columns) + "'";
  std::vector<std::string> optional;
  for (const std::string& name : columns) {
    if (std::find(required.begin(), required.end(), name) == required.end()) {
      optional.push_back(name);
    }
  }
  if (!optional.empty()) {
    text += " (columns in any order; optional: ";
    for (size_t i = 0; i < optional.size(); ++i) {
      text += (i > 0 ? ", " : "") + optional[i];
    }
    text += ")";
  }
  return text;
}

}  // namespace

CsvTable CsvTable::Read(const std::filesystem::path& path,
                        const std::vector<std::string>& columns,
                        const std::vector<std::string>& required) {
  const std::string data = ReadFileToString(path);
  CsvTable table;
  table.path_ = path;
  bool have_header = false;
  int line_number = 0;
  for (size_t pos = 0; pos < data.size();) {
    size_t end = data.find('\n', pos);
    if (end == std::string::npos) end = data.size();
    std::string line = data.substr(pos, end - pos);
    pos = end + 1;
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    line = Trim(line);
    if (line.empty() || line[0] == '#') continue;
    const std::string where = path.string() + ":" + std::to_string(line_number);
    if (line.find('"') != std::string::npos) {
      throw ErrorAt(where, ": quoted fields are not supported");
    }
    std::vector<std::string> fields = SplitFields(line);
    if (!have_header) {
      const std::string problem = HeaderProblem(fields, columns, required);
      if (!problem.empty()) {
        throw ErrorAt(where, ": expected the header ",
                      ExpectedHeader(columns, required), ", got '", line,
                      "': ", problem);
      }
      table.header_ = std::move(fields);
      have_header = true;
      continue;
    }
    if (fields.size() != table.header_.size()) {
      throw ErrorAt(where, ": expected ", table.header_.size(), " fields, got ",
                    fields.size());
    }
    table.rows_.push_back({line_number, std::move(fields)});
  }
  if (!have_header) {
    throw ErrorAt(path.string(), ": no header row ",
                  ExpectedHeader(columns, required));
  }
  return table;
}

bool CsvTable::HasColumn(const std::string& name) const {
  return std::find(header_.begin(), header_.end(), name) != header_.end();
}

std::string CsvTable::Where(size_t row) const {
  return path_.string() + ":" + std::to_string(rows_[row].line);
}

size_t CsvTable::ColumnIndex(const std::string& column) const {
  const auto found = std::find(header_.begin(), header_.end(), column);
  if (found == header_.end()) {
    throw ErrorAt(path_.string(), ": no column '", column, "'");
  }
  return static_cast<size_t>(found - header_.begin());
}

const std::string& CsvTable::Text(size_t row, const std::string& column) const {
  return rows_[row].fields[ColumnIndex(column)];
}

double CsvTable::Double(size_t row, const std::string& column) const {
  const std::string& field = Text(row, column);
  double value = 0.0;
  const auto [end, error] =
      std::from_chars(field.data(), field.data() + field.size(), value);
  if (error != std::errc() || end != field.data() + field.size() ||
      !std::isfinite(value)) {
    throw ErrorAt(Where(row), ": ", column, " must be a finite number, got '",
                  field, "'");
  }
  return value;
}

double CsvTable::NonNegativeDouble(size_t row,
                                   const std::string& column) const {
  const double value = Double(row, column);
  if (value < 0.0) {
    throw ErrorAt(Where(row), ": ", column, " must be >= 0, got '",
                  Text(row, column), "'");
  }
  return value;
}

int CsvTable::Int(size_t row, const std::string& column, int min) const {
  const std::string& field = Text(row, column);
  int value = 0;
  const auto [end, error] =
      std::from_chars(field.data(), field.data() + field.size(), value);
  if (error != std::errc() || end != field.data() + field.size() ||
      value < min) {
    throw ErrorAt(Where(row), ": ", column, " must be an integer >= ", min,
                  ", got '", field, "'");
  }
  return value;
}

}  // namespace uw
