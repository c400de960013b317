// The comma-separated text files of navigation (nav.csv, image_times.csv):
// comment lines starting with '#', blank lines, one header row naming the
// columns, then data rows. Fields are trimmed; quoting is not supported, so
// a field holding a quote is refused rather than misread. Every accessor
// throws uw::Error naming the file and the 1-based line.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace uw {

class CsvTable {
 public:
  // Reads the file and splits it into the header and data rows; checks
  // that every row has as many fields as the header. `columns` lists the
  // column names the file may have (any order, each at most once) and
  // `required` those it must have; any other header is an error that spells
  // out the expected one. Throws on a missing file, a missing header, or
  // no data rows.
  static CsvTable Read(const std::filesystem::path& path,
                       const std::vector<std::string>& columns,
                       const std::vector<std::string>& required);

  const std::filesystem::path& Path() const { return path_; }
  size_t NumRows() const { return rows_.size(); }
  bool HasColumn(const std::string& name) const;

  // "path:line" of a row, for messages.
  std::string Where(size_t row) const;
  int Line(size_t row) const { return rows_[row].line; }

  const std::string& Text(size_t row, const std::string& column) const;
  // A finite number.
  double Double(size_t row, const std::string& column) const;
  // A finite number >= 0.
  double NonNegativeDouble(size_t row, const std::string& column) const;
  // An integer >= min.
  int Int(size_t row, const std::string& column, int min) const;

 private:
  struct Row {
    int line = 0;
    std::vector<std::string> fields;
  };
  size_t ColumnIndex(const std::string& column) const;

  std::filesystem::path path_;
  std::vector<std::string> header_;
  std::vector<Row> rows_;
};

}  // namespace uw
