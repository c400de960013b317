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
      : TextFileReaderTest(
            "uw_image_times_test", "image_times.csv",
            [](const fs::path& path) { return ReadImageTimesCsv(path); }) {}
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
            where +
                "2: time: expected seconds or an ISO 8601 time (e.g. "
                "2024-10-08T17:53:20.25Z), got 'nan'");
  EXPECT_EQ(Error("image_name,time\na.png,1\na.png,2\n"),
            where + "3: image 'a.png' already has a row at line 2");
  EXPECT_EQ(Error("image_name,time\n,1\n"), where + "2: empty image_name");
  EXPECT_EQ(Error("image_name,time,dive\na.png,1,0\n"),
            where + "2: dive must be an integer >= 1, got '0'");
  EXPECT_EQ(Error("image_name,time\n"), path_.string() + ": no image rows");
  EXPECT_EQ(Error("image_name,t\na.png,1\n").substr(0, where.size() + 23),
            where + "1: expected the header ");
}

// Cameras write their local time; ISO 8601 with a zone, or with the zone
// given as --time_zone gives it, is read as Unix time.
TEST_F(ImageTimesTest, ReadsIsoTimesOnTheClocksZone) {
  const std::string text =
      "image_name,time\n"
      "a.png,2024-10-08T17:53:20.25Z\n"
      "b.png,\"2024-10-08 19:53:21+02:00\"\n"
      "c.png,2024-10-08T19:53:22.5\n";
  EXPECT_EQ(Error(text), path_.string() +
                             ":4: time: '2024-10-08T19:53:22.5' has no time "
                             "zone (Z or +hh:mm): a clock in local time is "
                             "ambiguous; give its zone (--time_zone)");
  const std::vector<ImageTime> times = ReadImageTimesCsv(path_, 7200);
  ASSERT_EQ(times.size(), 3u);
  EXPECT_EQ(times[0].time_s, 1728410000.25);
  EXPECT_EQ(times[1].time_s, 1728410001.0);
  EXPECT_EQ(times[2].time_s, 1728410002.5);
}

}  // namespace
}  // namespace uw
