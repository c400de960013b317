#include "colmap_plugins/nav/csv_table.h"

#include <gtest/gtest.h>

#include "colmap_plugins/nav/text_file_reader_test.h"
#include "common/util/error.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

class CsvTableTest : public TextFileReaderTest<CsvTable> {
 protected:
  CsvTableTest()
      : TextFileReaderTest(
            "uw_csv_table_test", "table.csv", [](const fs::path& path) {
              return CsvTable::Read(path, {"name", "a", "b"}, {"name", "a"});
            }) {}
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
  EXPECT_EQ(Error("name,a\n\"x,y\",1\n"),
            path_.string() + ":2: quoted fields are not supported");
  const CsvTable table =
      Read("name,a,b\nx,1.5,nan\nx,2,inf\nx,3,\nx,abc,1e400\nx,-2,-0.5\n");
  const auto message = [&](auto&& read) {
    try {
      read();
    } catch (const uw::Error& error) {
      return std::string(error.what());
    }
    return std::string("no error");
  };
  const std::string where = path_.string() + ":";
  EXPECT_EQ(message([&] { table.Double(0, "b"); }),
            where + "2: b must be a finite number, got 'nan'");
  EXPECT_EQ(message([&] { table.Double(1, "b"); }),
            where + "3: b must be a finite number, got 'inf'");
  EXPECT_EQ(message([&] { table.Double(2, "b"); }),
            where + "4: b must be a finite number, got ''");
  EXPECT_EQ(message([&] { table.Double(3, "b"); }),
            where + "5: b must be a finite number, got '1e400'");
  EXPECT_EQ(message([&] { table.Int(0, "a", 1); }),
            where + "2: a must be an integer >= 1, got '1.5'");
  EXPECT_EQ(message([&] { table.Int(3, "a", 1); }),
            where + "5: a must be an integer >= 1, got 'abc'");
  EXPECT_EQ(message([&] { table.Int(4, "a", 1); }),
            where + "6: a must be an integer >= 1, got '-2'");
  EXPECT_EQ(message([&] { table.NonNegativeDouble(4, "b"); }),
            where + "6: b must be >= 0, got '-0.5'");
  EXPECT_EQ(table.NonNegativeDouble(1, "a"), 2.0);
}

TEST_F(CsvTableTest, MissingFileIsNamed) {
  fs::remove(path_);
  try {
    CsvTable::Read(path_, {"a"}, {"a"});
    ADD_FAILURE() << "no error";
  } catch (const uw::Error& error) {
    EXPECT_NE(std::string(error.what()).find(path_.string()),
              std::string::npos);
  }
}

}  // namespace
}  // namespace uw
