// The comma-separated tables the report reads and writes (timings.csv,
// compare/table.csv, laserscale's items.csv and segments.csv): one header
// row, then data rows; fields may be double-quoted ("" is a quote inside),
// as the scripts and laserscale write labels with commas. Unlike the
// navigation reader (nav/csv_table.h), no comment lines and no column
// schema: the report shows what the producer wrote.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace uw {

struct CsvFile {
  std::filesystem::path path;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;  // each as long as the header
  std::vector<int> lines;                      // 1-based line of each row

  // Index of a column, or nullopt.
  std::optional<size_t> Column(const std::string& name) const;
  // The field of a column that must exist; throws uw::Error naming the file
  // and the missing column.
  const std::string& Field(size_t row, const std::string& column) const;
  // The field as a finite number, or nullopt when it is empty; throws
  // uw::Error naming file:line when it is something else.
  std::optional<double> Number(size_t row, const std::string& column) const;
};

// Throws uw::Error naming the file (and line): missing or unreadable file,
// no header, a row with another number of fields, an unterminated quote.
// Blank lines are skipped; CRLF line ends are accepted.
CsvFile ReadCsvFile(const std::filesystem::path& path);

// A field as written to a CSV file: quoted when it holds a comma, a quote
// or a line break.
std::string CsvField(const std::string& text);

}  // namespace uw
