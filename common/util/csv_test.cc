#include "common/util/csv.h"

#include <gtest/gtest.h>

#include "common/util/error.h"
#include "common/util/error_testing.h"
#include "tests/support/text_file_reader_test.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

// Input files (nav.csv, image_times.csv): a schema, comments, padding.
// The fixtures keep the names of the two readers these cases were written
// for (nav/csv_table, report/csv_file), so their CTest names stay.
class CsvTableTest : public TextFileReaderTest<CsvTable> {
 protected:
  CsvTableTest()
      : TextFileReaderTest(
            "uw_csv_test", "input.csv", [](const fs::path& path) {
              return CsvTable::Read(path, {"name", "a", "b"}, {"name", "a"});
            }) {}
};

// Tables our tools write (timings.csv, items.csv): any header, verbatim.
class CsvFile : public TextFileReaderTest<CsvTable> {
 protected:
  CsvFile()
      : TextFileReaderTest(
            "uw_csv_test", "table.csv",
            [](const fs::path& path) { return CsvTable::Read(path); }) {}
};

TEST_F(CsvTableTest, CommentsBlankLinesCrlfSpacesAndAnyColumnOrder) {
  const CsvTable table =
      Read("# comment\r\n\r\n b , name,a\r\n 2.5, x ,-1\n# later\n\n3,y,4");
  ASSERT_EQ(table.NumRows(), 2u);
  EXPECT_TRUE(table.HasColumn("b"));
  EXPECT_EQ(table.Text(0, "name"), "x");
  EXPECT_EQ(table.Double(0, "b"), 2.5);
  EXPECT_EQ(table.Int(0, "a", -5), -1);
  EXPECT_EQ(table.Line(1), 7);
  EXPECT_EQ(table.Where(1), path_.string() + ":7");
  EXPECT_EQ(Read("name,a\nx,1\n").HasColumn("b"), false);
}

TEST_F(CsvTableTest, HeaderErrorsSpellOutTheExpectedHeader) {
  const std::string expected =
      ":1: expected the header 'name,a,b' (columns in any order; optional: "
      "b), got '";
  EXPECT_EQ(Error("name,a,c\n"),
            path_.string() + expected + "name,a,c': unknown column 'c'");
  EXPECT_EQ(Error("name,a,a\n"),
            path_.string() + expected + "name,a,a': column 'a' appears twice");
  EXPECT_EQ(Error("name,b\n"),
            path_.string() + expected + "name,b': no column 'a'");
  EXPECT_EQ(Error("# only comments\n\n"),
            path_.string() +
                ": no header row 'name,a,b' (columns in any order; optional: "
                "b)");
  EXPECT_EQ(Read("name,a\n").NumRows(), 0u);
}

TEST_F(CsvTableTest, RowErrorsNameFileAndLine) {
  EXPECT_EQ(Error("name,a\nx,1,2\n"),
            path_.string() + ":2: expected 2 fields, got 3");
  // Quoted fields are read (the navigation reader used to refuse them).
  EXPECT_EQ(Read("name,a\n\"x,y\",1\n").Text(0, "name"), "x,y");
  const CsvTable table =
      Read("name,a,b\nx,1.5,nan\nx,2,inf\nx,3,\nx,abc,1e400\nx,-2,-0.5\n");
  const std::string where = path_.string() + ":";
  EXPECT_EQ(ErrorOf([&] { table.Double(0, "b"); }),
            where + "2: b must be a finite number, got 'nan'");
  EXPECT_EQ(ErrorOf([&] { table.Double(1, "b"); }),
            where + "3: b must be a finite number, got 'inf'");
  EXPECT_EQ(ErrorOf([&] { table.Double(2, "b"); }),
            where + "4: b must be a finite number, got ''");
  EXPECT_EQ(ErrorOf([&] { table.Double(3, "b"); }),
            where + "5: b must be a finite number, got '1e400'");
  EXPECT_EQ(ErrorOf([&] { table.Int(0, "a", 1); }),
            where + "2: a must be an integer >= 1, got '1.5'");
  EXPECT_EQ(ErrorOf([&] { table.Int(3, "a", 1); }),
            where + "5: a must be an integer >= 1, got 'abc'");
  EXPECT_EQ(ErrorOf([&] { table.Int(4, "a", 1); }),
            where + "6: a must be an integer >= 1, got '-2'");
  EXPECT_EQ(ErrorOf([&] { table.NonNegativeDouble(4, "b"); }),
            where + "6: b must be >= 0, got '-0.5'");
  EXPECT_EQ(table.NonNegativeDouble(1, "a"), 2.0);
}

// What R's write.csv and most loggers write: quoted names with commas,
// quotes and line breaks; padding outside the quotes is dropped, inside kept.
TEST_F(CsvTableTest, ReadsQuotedFieldsAsRfc4180) {
  const CsvTable table = Read(
      "# exported by \"the logger\", v2\n"
      "\"name\",\"a\"\n"
      " \" two, \"\"quoted\"\" \" , 1\n"
      "\"line\nbreak\",2\n"
      "plain,\"3\"\n"
      "padded,\" 4.5\t\"\n"
      "blank,\"  \"\n");
  ASSERT_EQ(table.NumRows(), 5u);
  EXPECT_EQ(table.Text(0, "name"), " two, \"quoted\" ");
  EXPECT_EQ(table.Int(0, "a", 0), 1);
  EXPECT_EQ(table.Text(1, "name"), "line\nbreak");
  EXPECT_EQ(table.Line(1), 4);
  EXPECT_EQ(table.Where(2), path_.string() + ":6");
  EXPECT_EQ(table.Double(2, "a"), 3.0);
  // A number padded inside its quotes is still that number; a name keeps
  // its padding (above), and padding alone is no number.
  EXPECT_EQ(table.Double(3, "a"), 4.5);
  EXPECT_THROW(table.Double(4, "a"), uw::Error);
  EXPECT_THROW(table.Int(4, "a", 0), uw::Error);
  EXPECT_EQ(Error("name,a\nx,1\n\"open,2\n"),
            path_.string() + ":3: unterminated quoted field");
  EXPECT_EQ(Error("name,a\n\"x\ny\",1,2\n"),
            path_.string() + ":2: expected 2 fields, got 3");
}

TEST_F(CsvTableTest, MissingFileIsNamed) {
  fs::remove(path_);
  EXPECT_NE(ErrorOf([&] {
              CsvTable::Read(path_, {"a"}, {"a"});
            }).find(path_.string()),
            std::string::npos);
}

// The files the scripts write: quoted labels with commas, CRLF, blank lines.
TEST_F(CsvFile, ReadsQuotedFieldsAndNumbers) {
  const CsvTable file = Read(
      "stage,seconds\r\n\"copy, the survey\",3\r\n\r\n\"say \"\"hi\"\"\",\n"
      "total,12.5\n");
  ASSERT_EQ(file.NumRows(), 3u);
  EXPECT_EQ(file.Text(0, "stage"), "copy, the survey");
  EXPECT_EQ(file.Text(1, "stage"), "say \"hi\"");
  EXPECT_EQ(file.Number(0, "seconds"), 3.0);
  EXPECT_FALSE(file.Number(1, "seconds").has_value());
  EXPECT_EQ(file.Number(2, "seconds"), 12.5);
  EXPECT_EQ((std::vector<int>{file.Line(0), file.Line(1), file.Line(2)}),
            (std::vector<int>{2, 4, 5}));
  EXPECT_FALSE(file.Column("time").has_value());
}

// No comments and no padding: a table shows what its producer wrote.
TEST_F(CsvFile, KeepsFieldsAsWritten) {
  const CsvTable file = Read("#,label\n1, padded \n");
  EXPECT_EQ(file.Header(), (std::vector<std::string>{"#", "label"}));
  EXPECT_EQ(file.Rows(),
            (std::vector<std::vector<std::string>>{{"1", " padded "}}));
}

TEST_F(CsvFile, WritesFieldsThatReadBack) {
  for (const std::string text :
       {"plain", "a,b", "say \"x\"", "two\nlines", "cr\r\nlf"}) {
    EXPECT_EQ(Read("name\n" + CsvField(text) + "\n").Text(0, "name"), text);
  }
  EXPECT_EQ(CsvField("plain"), "plain");
}

TEST_F(CsvFile, ErrorsNameTheFileAndLine) {
  EXPECT_NE(
      Error("a,b\n1,2\n3\n").find(path_.string() + ":3: expected 2 fields"),
      std::string::npos);
  EXPECT_NE(Error("a\n\"open\n").find(path_.string() + ":2: unterminated"),
            std::string::npos);
  EXPECT_NE(Error("\n\n").find(path_.string() + ": empty"), std::string::npos);
  const CsvTable file = Read("a,b\nx,1\n");
  EXPECT_NE(ErrorOf([&] {
              file.Number(0, "a");
            }).find(path_.string() + ":2: a must be"),
            std::string::npos);
  EXPECT_THROW(file.Text(0, "c"), uw::Error);
  fs::remove(path_);
  EXPECT_NE(ErrorOf([&] { CsvTable::Read(path_); }).find(path_.string()),
            std::string::npos);
}

}  // namespace
}  // namespace uw
