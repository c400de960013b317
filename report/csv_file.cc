#include "report/csv_file.h"

#include <cmath>
#include <cstdlib>

#include "common/util/error.h"
#include "common/util/file.h"

namespace uw {
namespace {

// Splits one record starting at `*at` (which ends past its line end) into
// fields; `*line` counts the line breaks consumed, quoted ones included.
std::vector<std::string> SplitRecord(const std::string& text, size_t* at,
                                     int* line, const std::string& where) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  const int first_line = *line;
  size_t i = *at;
  for (; i < text.size(); ++i) {
    const char c = text[i];
    if (quoted) {
      if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') {
        fields.back() += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        if (c == '\n') ++*line;
        fields.back() += c;
      }
    } else if (c == '"' && fields.back().empty()) {
      quoted = true;
    } else if (c == ',') {
      fields.emplace_back();
    } else if (c == '\n') {
      ++*line;
      ++i;
      break;
    } else if (c != '\r') {
      fields.back() += c;
    }
  }
  if (quoted) {
    throw ErrorAt(where, ":", first_line, ": unterminated quoted field");
  }
  *at = i;
  return fields;
}

}  // namespace

std::optional<size_t> CsvFile::Column(const std::string& name) const {
  for (size_t c = 0; c < header.size(); ++c) {
    if (header[c] == name) return c;
  }
  return std::nullopt;
}

const std::string& CsvFile::Field(size_t row, const std::string& column) const {
  const std::optional<size_t> c = Column(column);
  if (!c) {
    throw ErrorAt(path.string(), ": no column \"", column, "\"");
  }
  return rows.at(row)[*c];
}

std::optional<double> CsvFile::Number(size_t row,
                                      const std::string& column) const {
  const std::string& text = Field(row, column);
  if (text.empty()) return std::nullopt;
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size() || !std::isfinite(value)) {
    throw ErrorAt(path.string(), ":", lines.at(row), ": ", column,
                  " must be a finite number, got '", text, "'");
  }
  return value;
}

CsvFile ReadCsvFile(const std::filesystem::path& path) {
  const std::string text = ReadFileToString(path);
  CsvFile file;
  file.path = path;
  size_t at = 0;
  int line = 1;
  while (at < text.size()) {
    const int record_line = line;
    std::vector<std::string> fields =
        SplitRecord(text, &at, &line, path.string());
    if (fields.size() == 1 && fields[0].empty()) continue;  // blank line
    if (file.header.empty()) {
      file.header = std::move(fields);
      continue;
    }
    if (fields.size() != file.header.size()) {
      throw ErrorAt(path.string(), ":", record_line, ": expected ",
                    file.header.size(), " fields as the header, got ",
                    fields.size());
    }
    file.rows.push_back(std::move(fields));
    file.lines.push_back(record_line);
  }
  if (file.header.empty()) {
    throw ErrorAt(path.string(), ": empty (expected a header row)");
  }
  return file;
}

std::string CsvField(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string quoted = "\"";
  for (const char c : text) {
    if (c == '"') quoted += '"';
    quoted += c;
  }
  return quoted + "\"";
}

}  // namespace uw
