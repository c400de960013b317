#include "common/util/csv.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <string_view>

#include "common/util/error.h"
#include "common/util/file.h"
#include "common/util/number_text.h"
#include "common/util/time_text.h"

namespace uw {

// What a file may hold besides RFC 4180 records (csv.h).
struct CsvTable::Format {
  // An input file: '#' comment lines, padded fields, a column schema.
  bool input_file = false;
  std::vector<std::string> columns;
  std::vector<std::string> required;
  // With select: (our name, the file's name) pairs; the file's columns
  // neither renamed nor in `columns` are dropped.
  bool select = false;
  std::vector<std::pair<std::string, std::string>> ours_from_file;
};

namespace {

bool IsBlank(char c) { return c == ' ' || c == '\t'; }

// `text` without the spaces and tabs around it.
std::string_view Trim(std::string_view text) {
  const size_t first = text.find_first_not_of(" \t");
  if (first == std::string_view::npos) return {};
  return text.substr(first, text.find_last_not_of(" \t") - first + 1);
}

struct Record {
  std::vector<std::string> fields;
  std::string text;  // as in the file, without its line end
};

// Reads the record starting at `*at` and moves `*at` past its line end;
// `*line` counts the line breaks consumed, quoted ones included. With
// `trim`, spaces and tabs around a field that lie outside its quotes are
// not part of it.
Record ReadRecord(const std::string& text, size_t* at, int* line, bool trim,
                  const std::string& path) {
  const size_t start = *at;
  const int first_line = *line;
  Record record;
  record.fields.emplace_back();
  size_t quoted_end = 0;  // the current field's length at its last quote
  const auto end_field = [&] {
    std::string& field = record.fields.back();
    if (!trim) return;
    size_t keep = field.size();
    while (keep > quoted_end && IsBlank(field[keep - 1])) --keep;
    field.resize(keep);
  };
  bool quoted = false;
  size_t i = start;
  size_t end = text.size();
  for (; i < text.size(); ++i) {
    const char c = text[i];
    std::string& field = record.fields.back();
    if (quoted) {
      if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') {
        field += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
        quoted_end = field.size();
      } else {
        if (c == '\n') ++*line;
        field += c;
      }
    } else if (c == '"' && field.empty()) {
      quoted = true;
    } else if (c == ',') {
      end_field();
      record.fields.emplace_back();
      quoted_end = 0;
    } else if (c == '\n') {
      ++*line;
      end = i;
      ++i;
      break;
    } else if (c == '\r' && (i + 1 == text.size() || text[i + 1] == '\n')) {
      // The CR of a CRLF line end.
    } else if (!(trim && field.empty() && IsBlank(c))) {
      field += c;
    }
  }
  if (quoted) {
    throw ErrorAt(path, ":", first_line, ": unterminated quoted field");
  }
  end_field();
  record.text = text.substr(start, end - start);
  if (!record.text.empty() && record.text.back() == '\r') {
    record.text.pop_back();
  }
  *at = i;
  return record;
}

// Whether the line starting at `at` is a comment: '#' after spaces or tabs.
bool IsCommentLine(const std::string& text, size_t at) {
  while (at < text.size() && IsBlank(text[at])) ++at;
  return at < text.size() && text[at] == '#';
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

// The header's columns under our names: the renamed ones and those already
// named as `columns` lists; `kept` gets their indices in the file.
std::vector<std::string> SelectColumns(
    const std::vector<std::string>& header,
    const std::vector<std::string>& columns,
    const std::vector<std::pair<std::string, std::string>>& ours_from_file,
    const std::string& where, std::vector<size_t>* kept) {
  std::vector<std::string> names;
  for (size_t k = 0; k < header.size(); ++k) {
    const auto renamed = std::find_if(
        ours_from_file.begin(), ours_from_file.end(),
        [&](const auto& pair) { return pair.second == header[k]; });
    if (renamed != ours_from_file.end()) {
      names.push_back(renamed->first);
    } else if (std::find(columns.begin(), columns.end(), header[k]) !=
               columns.end()) {
      names.push_back(header[k]);
    } else {
      continue;
    }
    kept->push_back(k);
  }
  for (const auto& [ours, file] : ours_from_file) {
    if (std::find(header.begin(), header.end(), file) == header.end()) {
      throw ErrorAt(where, ": no column '", file, "' (mapped to ", ours,
                    ") in the header '", Join(header), "'");
    }
  }
  return names;
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
  return Parse(path, Format{true, columns, required, false, {}});
}

CsvTable CsvTable::Read(
    const std::filesystem::path& path, const std::vector<std::string>& columns,
    const std::vector<std::string>& required,
    const std::vector<std::pair<std::string, std::string>>& ours_from_file) {
  return Parse(path, Format{true, columns, required, true, ours_from_file});
}

CsvTable CsvTable::Read(const std::filesystem::path& path) {
  return Parse(path, Format{});
}

CsvTable CsvTable::Parse(const std::filesystem::path& path,
                         const Format& format) {
  const std::string text = ReadFileToString(path);
  CsvTable table;
  table.path_ = path;
  bool have_header = false;
  size_t file_columns = 0;
  std::vector<size_t> kept;  // with select: the file's columns kept, in order
  size_t at = 0;
  int line = 1;
  while (at < text.size()) {
    const int record_line = line;
    if (format.input_file && IsCommentLine(text, at)) {
      const size_t end = text.find('\n', at);
      at = end == std::string::npos ? text.size() : end + 1;
      ++line;
      continue;
    }
    Record record =
        ReadRecord(text, &at, &line, format.input_file, path.string());
    if (record.fields.size() == 1 && record.fields[0].empty()) continue;
    const std::string where = path.string() + ":" + std::to_string(record_line);
    if (!have_header) {
      file_columns = record.fields.size();
      if (format.select) {
        record.fields = SelectColumns(record.fields, format.columns,
                                      format.ours_from_file, where, &kept);
      }
      if (format.input_file) {
        const std::string problem =
            HeaderProblem(record.fields, format.columns, format.required);
        if (!problem.empty()) {
          throw ErrorAt(where, ": expected the header ",
                        ExpectedHeader(format.columns, format.required),
                        ", got '", Trim(record.text), "': ", problem);
        }
      }
      table.header_ = std::move(record.fields);
      have_header = true;
      continue;
    }
    if (record.fields.size() != file_columns) {
      throw ErrorAt(where, ": expected ", file_columns, " fields, got ",
                    record.fields.size());
    }
    if (format.select) {
      std::vector<std::string> fields;
      for (const size_t k : kept) fields.push_back(std::move(record.fields[k]));
      record.fields = std::move(fields);
    }
    table.rows_.push_back(std::move(record.fields));
    table.lines_.push_back(record_line);
  }
  if (!have_header) {
    if (format.input_file) {
      throw ErrorAt(path.string(), ": no header row ",
                    ExpectedHeader(format.columns, format.required));
    }
    throw ErrorAt(path.string(), ": empty (expected a header row)");
  }
  return table;
}

std::optional<size_t> CsvTable::Column(const std::string& name) const {
  const auto found = std::find(header_.begin(), header_.end(), name);
  if (found == header_.end()) return std::nullopt;
  return static_cast<size_t>(found - header_.begin());
}

bool CsvTable::HasColumn(const std::string& name) const {
  return Column(name).has_value();
}

std::string CsvTable::Where(size_t row) const {
  return path_.string() + ":" + std::to_string(lines_[row]);
}

const std::string& CsvTable::Text(size_t row, const std::string& column) const {
  const std::optional<size_t> index = Column(column);
  if (!index) {
    throw ErrorAt(path_.string(), ": no column '", column, "'");
  }
  return rows_.at(row)[*index];
}

double CsvTable::Double(size_t row, const std::string& column) const {
  const std::string& field = Text(row, column);
  // Without the padding a quoted export may give a number (" 12.5 "): a
  // name keeps its padding (it is text), a number does not need it.
  const std::optional<double> value = FiniteDouble(Trim(field));
  if (!value) {
    throw ErrorAt(Where(row), ": ", column, " must be a finite number, got '",
                  field, "'");
  }
  return *value;
}

double CsvTable::Time(size_t row, const std::string& column,
                      std::optional<int> zone_offset_s) const {
  return ParseTimeField(Text(row, column), Where(row) + ": " + column,
                        zone_offset_s);
}

std::optional<double> CsvTable::Number(size_t row,
                                       const std::string& column) const {
  if (Trim(Text(row, column)).empty()) return std::nullopt;
  return Double(row, column);
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
  const std::string_view text = Trim(field);
  int value = 0;
  const auto [end, error] =
      std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || error != std::errc() ||
      end != text.data() + text.size() || value < min) {
    throw ErrorAt(Where(row), ": ", column, " must be an integer >= ", min,
                  ", got '", field, "'");
  }
  return value;
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
