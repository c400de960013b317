// Comma-separated text files, read and written by one set of rules: RFC 4180
// records (a field may be double-quoted; inside quotes "" is a quote, and
// commas and line breaks are text, as R and most loggers write them), one
// header row naming the columns, blank lines skipped, CRLF accepted. Every
// error is a uw::Error naming the file and the 1-based line.
//
// Two kinds of file use it:
// - input files people and loggers write (nav.csv, image_times.csv, dive
//   lists): a schema of allowed and required columns, '#' comment lines, and
//   spaces or tabs around a field that are not part of it;
// - tables our tools and scripts write for the report (timings.csv,
//   compare/table.csv, laserscale's items.csv and segments.csv): any header,
//   every field exactly as written.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace uw {

class CsvTable {
 public:
  // An input file. `columns` lists the names the header may hold (any order,
  // each at most once) and `required` those it must hold; another header is
  // an error that spells out the expected one. Lines whose first non-blank
  // character is '#' are comments; spaces and tabs around a field are
  // dropped (inside quotes they are kept).
  static CsvTable Read(const std::filesystem::path& path,
                       const std::vector<std::string>& columns,
                       const std::vector<std::string>& required);
  // The same for a file whose header names its columns otherwise (an
  // export): `ours_from_file` renames some of the file's columns ("Latitude"
  // to "lat"); its other columns keep their names when `columns` lists them
  // and are ignored otherwise. A renamed column the header lacks is an
  // error naming it.
  static CsvTable Read(
      const std::filesystem::path& path,
      const std::vector<std::string>& columns,
      const std::vector<std::string>& required,
      const std::vector<std::pair<std::string, std::string>>& ours_from_file);
  // A table of any header whose fields are kept exactly as written.
  static CsvTable Read(const std::filesystem::path& path);

  const std::filesystem::path& Path() const { return path_; }
  const std::vector<std::string>& Header() const { return header_; }
  // Each row as long as the header.
  const std::vector<std::vector<std::string>>& Rows() const { return rows_; }
  size_t NumRows() const { return rows_.size(); }
  // Index of a column, or nullopt.
  std::optional<size_t> Column(const std::string& name) const;
  bool HasColumn(const std::string& name) const;

  // The 1-based line a row starts on, and "path:line" for messages.
  int Line(size_t row) const { return lines_[row]; }
  std::string Where(size_t row) const;

  // The accessors below throw uw::Error naming the file when the column does
  // not exist, and file:line when the field is not what they expect.
  const std::string& Text(size_t row, const std::string& column) const;
  // A finite number; spaces and tabs around it (a quoted export's " 12.5 ")
  // are allowed.
  double Double(size_t row, const std::string& column) const;
  // A time: seconds as a number, or ISO 8601 (ParseTimeField) read on the
  // clock `zone_offset_s` east of UTC when it states no zone.
  double Time(size_t row, const std::string& column,
              std::optional<int> zone_offset_s = std::nullopt) const;
  // A finite number, or nullopt when the field is empty or blank.
  std::optional<double> Number(size_t row, const std::string& column) const;
  // A finite number >= 0.
  double NonNegativeDouble(size_t row, const std::string& column) const;
  // An integer >= min, spaces and tabs around it allowed.
  int Int(size_t row, const std::string& column, int min) const;

 private:
  struct Format;
  static CsvTable Parse(const std::filesystem::path& path,
                        const Format& format);

  std::filesystem::path path_;
  std::vector<std::string> header_;
  std::vector<std::vector<std::string>> rows_;
  std::vector<int> lines_;
};

// A field as written to a CSV file: quoted when it holds a comma, a quote or
// a line break, so that CsvTable reads it back unchanged.
std::string CsvField(const std::string& text);

}  // namespace uw
