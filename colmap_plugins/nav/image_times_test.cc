#include "colmap_plugins/nav/image_times.h"

#include <gtest/gtest.h>

#include "common/util/error.h"
#include "tests/support/text_file_reader_test.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

class ImageTimesTest : public TextFileReaderTest<std::vector<ImageTime>> {
 protected:
  ImageTimesTest()
      : TextFileReaderTest("uw_image_times_test", "image_times.csv",
                           ReadImageTimesCsv) {}
};

TEST_F(ImageTimesTest, ReadsUwsimsFileAndAnOptionalDive) {
  std::vector<ImageTime> times = Read(
      "# uwsim image times: seconds since the survey's start\n"
      "image_name,time\n"
      "cam1/00000.png,0\n"
      "cam2/00000.png,0.20000000000000001\n");
  ASSERT_EQ(times.size(), 2u);
  EXPECT_EQ(times[1].image_name, "cam2/00000.png");
  EXPECT_EQ(times[1].time_s, 0.2);
  EXPECT_EQ(times[1].dive, 0);
  EXPECT_EQ(times[1].line, 4);
  // Times may go back: they are the images', in any order.
  times = Read("dive,image_name,time\n2,a.png,7.5\n1,b.png,3\n");
  ASSERT_EQ(times.size(), 2u);
  EXPECT_EQ(times[0].dive, 2);
  EXPECT_EQ(times[1].time_s, 3.0);
}

TEST_F(ImageTimesTest, BadRowsNameFileAndLine) {
  const std::string where = path_.string() + ":";
  EXPECT_EQ(Error("image_name,time\na.png,nan\n"),
            where + "2: time must be a finite number, got 'nan'");
  EXPECT_EQ(Error("image_name,time\na.png,1\na.png,2\n"),
            where + "3: image 'a.png' already has a row at line 2");
  EXPECT_EQ(Error("image_name,time\n,1\n"), where + "2: empty image_name");
  EXPECT_EQ(Error("image_name,time,dive\na.png,1,0\n"),
            where + "2: dive must be an integer >= 1, got '0'");
  EXPECT_EQ(Error("image_name,time\n"), path_.string() + ": no image rows");
  EXPECT_EQ(Error("image_name,t\na.png,1\n").substr(0, where.size() + 23),
            where + "1: expected the header ");
}

}  // namespace
}  // namespace uw
