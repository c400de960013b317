#include "report/csv_file.h"

#include <gtest/gtest.h>

#include <fstream>

#include "common/util/error.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

fs::path WriteText(const std::string& name, const std::string& text) {
  const fs::path path = fs::path(::testing::TempDir()) / name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

std::string ReadError(const fs::path& path) {
  try {
    ReadCsvFile(path);
  } catch (const Error& error) {
    return error.what();
  }
  ADD_FAILURE() << "no error reading " << path;
  return "";
}

// The files the scripts write: quoted labels with commas, CRLF, blank lines.
TEST(CsvFile, ReadsQuotedFieldsAndNumbers) {
  const fs::path path = WriteText(
      "csv_quoted.csv",
      "stage,seconds\r\n\"copy, the survey\",3\r\n\r\n\"say \"\"hi\"\"\",\n"
      "total,12.5\n");
  const CsvFile file = ReadCsvFile(path);
  ASSERT_EQ(file.rows.size(), 3u);
  EXPECT_EQ(file.Field(0, "stage"), "copy, the survey");
  EXPECT_EQ(file.Field(1, "stage"), "say \"hi\"");
  EXPECT_EQ(file.Number(0, "seconds"), 3.0);
  EXPECT_FALSE(file.Number(1, "seconds").has_value());
  EXPECT_EQ(file.Number(2, "seconds"), 12.5);
  EXPECT_EQ(file.lines, (std::vector<int>{2, 4, 5}));
  EXPECT_FALSE(file.Column("time").has_value());
}

TEST(CsvFile, WritesFieldsThatReadBack) {
  for (const std::string text : {"plain", "a,b", "say \"x\"", "two\nlines"}) {
    const fs::path path =
        WriteText("csv_round_trip.csv", "name\n" + CsvField(text) + "\n");
    EXPECT_EQ(ReadCsvFile(path).Field(0, "name"), text);
  }
  EXPECT_EQ(CsvField("plain"), "plain");
}

TEST(CsvFile, ErrorsNameTheFileAndLine) {
  const fs::path short_row = WriteText("csv_short.csv", "a,b\n1,2\n3\n");
  EXPECT_NE(ReadError(short_row).find("csv_short.csv:3: expected 2 fields"),
            std::string::npos);
  const fs::path open_quote = WriteText("csv_quote.csv", "a\n\"open\n");
  EXPECT_NE(ReadError(open_quote).find("csv_quote.csv:2: unterminated"),
            std::string::npos);
  const fs::path empty = WriteText("csv_empty.csv", "\n\n");
  EXPECT_NE(ReadError(empty).find("csv_empty.csv: empty"), std::string::npos);
  EXPECT_NE(ReadError(fs::path(::testing::TempDir()) / "csv_none.csv")
                .find("csv_none.csv"),
            std::string::npos);
  const CsvFile file = ReadCsvFile(WriteText("csv_bad.csv", "a,b\nx,1\n"));
  try {
    file.Number(0, "a");
    ADD_FAILURE() << "no error";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("csv_bad.csv:2: a must be"),
              std::string::npos);
  }
  EXPECT_THROW(file.Field(0, "c"), Error);
}

}  // namespace
}  // namespace uw
