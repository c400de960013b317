#include "common/util/file.h"

#include <gtest/gtest.h>

#include <fstream>

#include "common/util/error.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

fs::path EmptyDir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / "uw_file_test" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

TEST(WriteFilesAtomically, WritesAllFiles) {
  const fs::path dir = EmptyDir("writes");
  WriteFilesAtomically(
      {{dir / "a" / "x.txt", [](std::ostream& s) { s << "x"; }},
       {dir / "y.txt", [](std::ostream& s) { s << "y"; }}},
      false);
  EXPECT_EQ(ReadFileToString(dir / "a" / "x.txt"), "x");
  EXPECT_EQ(ReadFileToString(dir / "y.txt"), "y");
  EXPECT_EQ(
      std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 2);
}

TEST(WriteFilesAtomically, FailureLeavesTheFileSystemAsItWas) {
  const fs::path dir = EmptyDir("failure");
  std::ofstream(dir / "keep.txt") << "old";
  const auto failing = [](std::ostream&) { throw Error("writer failed"); };
  EXPECT_THROW(WriteFilesAtomically(
                   {{dir / "keep.txt", [](std::ostream& s) { s << "new"; }},
                    {dir / "new" / "deeper" / "z.txt", failing}},
                   false),
               Error);
  // The old file is untouched, temporaries and created folders are gone.
  EXPECT_EQ(ReadFileToString(dir / "keep.txt"), "old");
  std::vector<std::string> left;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    left.push_back(entry.path().lexically_relative(dir).string());
  }
  EXPECT_EQ(left, std::vector<std::string>{"keep.txt"});
}

TEST(ReadFileToString, NamesAMissingFile) {
  try {
    ReadFileToString("/nonexistent/uw/file");
    FAIL();
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("/nonexistent/uw/file"),
              std::string::npos);
  }
}

}  // namespace
}  // namespace uw
