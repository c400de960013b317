#include "colmap_plugins/nav/nav_csv.h"

#include <algorithm>
#include <cmath>
#include <fstream>

#include <gtest/gtest.h>

#include "common/util/error.h"
#include "common/util/error_testing.h"
#include "tests/support/text_file_reader_test.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

constexpr double kDegToRad = M_PI / 180.0;
const std::string kHeader =
    "image_name,time,dive,x,y,z,roll,pitch,yaw,std_x,std_y,std_z,std_roll,"
    "std_pitch,std_yaw\n";

class NavCsvTest : public TextFileReaderTest<std::vector<NavRecord>> {
 protected:
  NavCsvTest()
      : TextFileReaderTest(
            "uw_nav_csv_test", "nav.csv",
            [](const fs::path& path) { return ReadNavigationCsv(path); }) {}
};

// A row of uwsim's nav.csv: angles in degrees become radians.
TEST_F(NavCsvTest, ReadsUwsimsLog) {
  const std::vector<NavRecord> nav =
      Read("# uwsim navigation: ...\n" + kHeader +
           "cam1/00000.png,0,1,-7.1058713602344072,-4.52,2.67,1.3795,-0.0287,"
           "-0.3860,0.9731,0.9731,0.02,0.05,0.05,0.2\n"
           "cam1/00001.png,1.5,1,-6,-4.5,2.6,0,0,90,1,1,0.02,0.05,0.05,0.2\n"
           "cam1/00002.png,0.5,2,-6,-4.5,2.6,0,0,90,1,1,0.02,0.05,0.05,0.2\n");
  ASSERT_EQ(nav.size(), 3u);
  const NavRecord& row = nav[0];
  EXPECT_EQ(row.image_name, "cam1/00000.png");
  EXPECT_EQ(row.time_s, 0.0);
  EXPECT_EQ(row.dive, 1);
  EXPECT_EQ(row.position, Eigen::Vector3d(-7.1058713602344072, -4.52, 2.67));
  EXPECT_EQ(row.rpy_rad, Eigen::Vector3d(1.3795, -0.0287, -0.3860) * kDegToRad);
  EXPECT_EQ(row.position_sigma, Eigen::Vector3d(0.9731, 0.9731, 0.02));
  EXPECT_EQ(row.rpy_sigma_rad, Eigen::Vector3d(0.05, 0.05, 0.2) * kDegToRad);
  EXPECT_EQ(row.line, 3);
  EXPECT_EQ(nav[1].rpy_rad.z(), M_PI / 2);
  // Time runs per dive: dive 2 may start before dive 1 ends.
  EXPECT_EQ(nav[2].dive, 2);
}

// A log sampled at its own times: no image names, one dive.
TEST_F(NavCsvTest, ImageNameAndDiveColumnsAreOptional) {
  const std::vector<NavRecord> nav = Read(
      "yaw,time,x,y,z,roll,pitch,std_x,std_y,std_z,std_roll,std_pitch,"
      "std_yaw\n"
      "10,0.1,1,2,3,4,5,0,0,0,0,0,0\n"
      "11,0.2,1,2,3,4,5,0,0,0,0,0,0\n");
  ASSERT_EQ(nav.size(), 2u);
  EXPECT_EQ(nav[1].image_name, "");
  EXPECT_EQ(nav[1].dive, 1);
  EXPECT_EQ(nav[1].rpy_rad, Eigen::Vector3d(4, 5, 11) * kDegToRad);
  EXPECT_EQ(nav[1].position, Eigen::Vector3d(1, 2, 3));
}

// A logger's export: every field quoted, CRLF line ends, an image name with
// a comma and a quote in it, numbers padded inside their quotes.
TEST_F(NavCsvTest, QuotedExportsAreRead) {
  const std::vector<NavRecord> nav = Read(
      "\"image_name\",\"time\",\"x\",\"y\",\"z\",\"roll\",\"pitch\","
      "\"yaw\",\"std_x\",\"std_y\",\"std_z\",\"std_roll\",\"std_pitch\","
      "\"std_yaw\"\r\n"
      "\"dive 3, \"\"left\"\"/0001.png\",\" 12.5 \",\"1\",\"2\",\"3\","
      "\"0\",\"0\",\"90\",\"0.5\",\"0.5\",\"0.1\",\"1\",\"1\",\"2\"\r\n");
  ASSERT_EQ(nav.size(), 1u);
  EXPECT_EQ(nav[0].image_name, "dive 3, \"left\"/0001.png");
  EXPECT_EQ(nav[0].time_s, 12.5);
  EXPECT_EQ(nav[0].position, Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(nav[0].rpy_rad.z(), 90 * kDegToRad);
  EXPECT_EQ(nav[0].position_sigma, Eigen::Vector3d(0.5, 0.5, 0.1));
}

// A USBL export: positions only, no sigmas. Nothing is invented for what
// was not logged.
TEST_F(NavCsvTest, PositionOnlyLogsAreRead) {
  const std::vector<NavRecord> nav =
      Read("image_name,time,x,y,z\na.png,0,1,2,3\nb.png,1,4,5,6\n");
  ASSERT_EQ(nav.size(), 2u);
  EXPECT_FALSE(nav[1].has_roll_pitch);
  EXPECT_FALSE(nav[1].has_yaw);
  EXPECT_EQ(nav[1].position, Eigen::Vector3d(4, 5, 6));
  EXPECT_EQ(nav[1].rpy_rad, Eigen::Vector3d::Zero());
  EXPECT_EQ(nav[1].position_sigma, Eigen::Vector3d::Zero());
  // Stated position sigmas, and roll and pitch without yaw.
  const std::vector<NavRecord> levelled = Read(
      "time,x,y,z,std_x,std_y,std_z,roll,pitch\n0,1,2,3,0.5,0.5,0.1,2,3\n");
  EXPECT_TRUE(levelled[0].has_roll_pitch);
  EXPECT_FALSE(levelled[0].has_yaw);
  EXPECT_EQ(levelled[0].position_sigma, Eigen::Vector3d(0.5, 0.5, 0.1));
  EXPECT_EQ(levelled[0].rpy_rad, Eigen::Vector3d(2, 3, 0) * kDegToRad);
  EXPECT_EQ(levelled[0].rpy_sigma_rad, Eigen::Vector3d::Zero());
}

// Loggers write ISO 8601 times (a USBL export's "2024-10-08T17:53:20.25Z");
// they are read as Unix time, the zone applied; one without a zone needs
// the clock's zone, or it would be a guess hours off.
TEST_F(NavCsvTest, IsoTimesAreReadAsUnixTimes) {
  const std::vector<NavRecord> nav = Read(
      "time,x,y,z\n2024-10-08T17:53:20.25Z,1,2,3\n"
      "2024-10-08T19:53:21.5+02:00,4,5,6\n1728410002,7,8,9\n");
  ASSERT_EQ(nav.size(), 3u);
  EXPECT_EQ(nav[0].time_s, 1728410000.25);
  EXPECT_EQ(nav[1].time_s, 1728410001.5);
  EXPECT_EQ(nav[2].time_s, 1728410002.0);
  const std::string local = "time,x,y,z\n2024-10-08 10:53:20,1,2,3\n";
  EXPECT_NE(Error(local).find(":2: time: '2024-10-08 10:53:20' has no time "
                              "zone"),
            std::string::npos);
  EXPECT_EQ(
      ReadNavigationCsv(path_, std::nullopt, nullptr, -7 * 3600)[0].time_s,
      1728410000.0);
}

// A vehicle's export, as it comes: its own column names (quoted, with
// spaces and units), columns we do not read, ISO times. --columns maps
// ours to theirs and the rest is ignored.
TEST_F(NavCsvTest, AnExportIsReadThroughAColumnMap) {
  Read("x,y,z,time\n1,2,3,0\n");  // writes path_; replaced below
  std::ofstream(path_, std::ios::binary)
      << "\"Time\",\"Latitude\",\"Longitude\",\"Depth (m)\",\"Heading\","
         "\"Battery V\"\n"
         "2024-10-08T17:53:20.25Z,43.1,5.4,10.5,90,15.2\n"
         "2024-10-08T17:53:21.25Z,43.1001,5.4,10.6,91,15.1\n";
  const NavColumnMap map = NavColumnMapFromText(
      "time=Time,lat=Latitude,lon=Longitude,depth=Depth (m),heading=Heading",
      "--columns");
  EXPECT_EQ(NavColumnMapText(map),
            "time=Time,lat=Latitude,lon=Longitude,depth=Depth (m),"
            "heading=Heading");
  NavLogFrame frame;
  const std::vector<NavRecord> nav = ReadNavigationCsv(
      path_, GeoOrigin{43.1, 5.4, 0.0}, &frame, std::nullopt, map);
  ASSERT_EQ(nav.size(), 2u);
  EXPECT_EQ(frame.position_columns, "lat,lon,depth");
  EXPECT_EQ(nav[1].time_s, 1728410001.25);
  EXPECT_NEAR(nav[1].position.y(), 11.1, 0.1);  // 1e-4 deg north
  EXPECT_TRUE(nav[1].position.isApprox(
      LocalEnu(GeoOrigin{43.1, 5.4, 0.0}).FromGeodetic(43.1001, 5.4, -10.6),
      1e-12));
  EXPECT_TRUE(nav[1].has_yaw);
  // A mapped column the file lacks, and maps that cannot be.
  ExpectErrorContaining(
      [&] {
        ReadNavigationCsv(path_, GeoOrigin{43.1, 5.4, 0.0}, nullptr,
                          std::nullopt,
                          NavColumnMapFromText("time=Time,lat=Latitude,lon="
                                               "Longitude,depth=Depth",
                                               "--columns"));
      },
      ":1: no column 'Depth' (mapped to depth) in the header");
  ExpectErrorContaining([] { NavColumnMapFromText("lat", "--columns"); },
                        "--columns: 'lat' is not ours=theirs");
  ExpectErrorContaining(
      [] { NavColumnMapFromText("latitude=Lat", "--columns"); },
      "'latitude' is not a nav.csv column");
  ExpectErrorContaining(
      [] { NavColumnMapFromText("lat=A,lat=B", "--columns"); },
      "'lat' given twice");
}

// Heading turns clockwise from north; yaw counter-clockwise from east.
TEST_F(NavCsvTest, HeadingIsReadAsYaw) {
  const std::vector<NavRecord> nav = Read(
      "time,x,y,z,heading,std_heading\n0,1,2,3,0,2\n1,1,2,3,90,2\n"
      "2,1,2,3,225,2\n");
  ASSERT_EQ(nav.size(), 3u);
  EXPECT_FALSE(nav[0].has_roll_pitch);
  EXPECT_TRUE(nav[0].has_yaw);
  EXPECT_DOUBLE_EQ(nav[0].rpy_rad.z(), M_PI / 2);          // north
  EXPECT_DOUBLE_EQ(nav[1].rpy_rad.z(), 0.0);               // east
  EXPECT_DOUBLE_EQ(nav[2].rpy_rad.z(), -135 * kDegToRad);  // south-west
  EXPECT_EQ(nav[2].rpy_sigma_rad, Eigen::Vector3d(0, 0, 2 * kDegToRad));
}

TEST_F(NavCsvTest, ColumnsThatComeTogetherAreChecked) {
  const std::string where = path_.string() + ":1: ";
  const struct {
    std::string header;
    std::string message;
  } cases[] = {
      {"time,x,y,z,roll",
       "the columns roll, pitch come together or not at all"},
      {"time,x,y,z,std_x,std_y",
       "the columns std_x, std_y, std_z come together or not at all"},
      {"time,x,y,z,yaw,heading", "yaw and heading say the same; give one"},
      {"time,x,y,z,yaw,std_yaw,std_heading",
       "std_yaw and std_heading say the same; give one"},
      {"time,x,y,z,std_yaw",
       "std_yaw is the sigma of yaw or heading, which "
       "the log does not have"},
      {"time,x,y,z,yaw,std_roll,std_pitch",
       "std_roll and std_pitch are the sigmas of roll and pitch, which the "
       "log does not have"},
  };
  for (const auto& test : cases) {
    const std::string text =
        test.header + "\n" +
        std::string(std::count(test.header.begin(), test.header.end(), ','),
                    ',') +
        "\n";
    EXPECT_EQ(Error(text), where + test.message) << test.header;
  }
}

// A USBL's WGS84 fixes: metres east, north and up of the origin, heading at
// each fix. Without an origin, the first fix rounded to 1e-3 deg is used and
// said; an origin for an x,y,z log is refused.
TEST_F(NavCsvTest, GeographicLogsAreReadIntoTheLocalFrame) {
  const std::string text =
      "time,lat,lon,depth,heading,std_x,std_y,std_z\n"
      "1,43.12345,5.45678,12.5,30,0.5,0.5,0.1\n"
      "2,43.12355,5.45688,13.0,31,0.5,0.5,0.1\n";
  const GeoOrigin origin{43.1234, 5.4567, 0.0};
  std::ofstream(path_, std::ios::binary) << text;
  NavLogFrame frame;
  const std::vector<NavRecord> nav = ReadNavigationCsv(path_, origin, &frame);
  ASSERT_EQ(nav.size(), 2u);
  const LocalEnu local(origin);
  EXPECT_LT(
      (nav[1].position - local.FromGeodetic(43.12355, 5.45688, -13.0)).norm(),
      1e-9);
  EXPECT_NEAR(nav[1].rpy_rad(2),
              local.YawFromHeading(31.0, 43.12355, 5.45688, -13.0) * kDegToRad,
              1e-12);
  EXPECT_EQ(nav[1].position_sigma, Eigen::Vector3d(0.5, 0.5, 0.1));
  EXPECT_FALSE(nav[1].has_roll_pitch);
  EXPECT_EQ(frame.position_columns, "lat,lon,depth");
  EXPECT_FALSE(frame.origin_automatic);

  const std::vector<NavRecord> automatic =
      ReadNavigationCsv(path_, std::nullopt, &frame);
  ASSERT_TRUE(frame.origin);
  EXPECT_TRUE(frame.origin_automatic);
  EXPECT_NEAR(frame.origin->lat_deg, 43.123, 1e-12);
  EXPECT_NEAR(frame.origin->lon_deg, 5.457, 1e-12);
  // Another origin moves the log, not its shape.
  EXPECT_NEAR((automatic[1].position - automatic[0].position).norm(),
              (nav[1].position - nav[0].position).norm(), 1e-9);

  std::ofstream(path_, std::ios::binary) << "time,x,y,z\n1,0,0,0\n";
  ExpectErrorContaining([&] { ReadNavigationCsv(path_, origin); },
                        "an origin is for a geographic log");
}

// The same fixes as UTM (zone 31, north) and as lat,lon,alt.
TEST_F(NavCsvTest, UtmAndAltitudeLogsAreTheSameFixes) {
  const GeoOrigin origin{0.5, 3.0, 0.0};
  std::ofstream(path_, std::ios::binary)
      << "time,easting,northing,zone,alt\n1,500000,0,31N,-4\n";
  const std::vector<NavRecord> utm = ReadNavigationCsv(path_, origin);
  std::ofstream(path_, std::ios::binary) << "time,lat,lon,alt\n1,0,3,-4\n";
  const std::vector<NavRecord> lat_lon = ReadNavigationCsv(path_, origin);
  EXPECT_LT((utm[0].position - lat_lon[0].position).norm(), 1e-6);
  // 0.5 deg south on the tangent plane: the meridian's radius at the
  // equator, a (1 - e^2), times sin(0.5 deg).
  EXPECT_NEAR(utm[0].position.y(), -6335439.327 * std::sin(0.5 * kDegToRad),
              0.1);
}

TEST_F(NavCsvTest, BadRowsNameFileAndLine) {
  const std::string good = "a.png,0,1,4,2,3,0,0,0,1,1,0.02,0.05,0.05,0.2\n";
  const std::string where = path_.string() + ":";
  const struct {
    std::string text;
    std::string message;
  } cases[] = {
      {kHeader + good + "b.png,1,1,9,2\n", where + "3: expected 15 fields"},
      {kHeader + "b.png,1,1,9,nan,3,0,0,0,1,1,0.02,0.05,0.05,0.2\n",
       where + "2: y must be a finite number, got 'nan'"},
      {kHeader + "b.png,1,1,9,2,3,0,0,-inf,1,1,0.02,0.05,0.05,0.2\n",
       where + "2: yaw must be a finite number, got '-inf'"},
      {kHeader + "b.png,1,1,9,2,3,0,0,0,1,-1,0.02,0.05,0.05,0.2\n",
       where + "2: std_y must be >= 0, got '-1'"},
      {kHeader + "b.png,1,1,9,2,3,0,0,0,1,1,0.02,0.05,-0.05,0.2\n",
       where + "2: std_pitch must be >= 0"},
      {kHeader + "b.png,1,0,9,2,3,0,0,0,1,1,0.02,0.05,0.05,0.2\n",
       where + "2: dive must be an integer >= 1, got '0'"},
      {kHeader + ",1,1,9,2,3,0,0,0,1,1,0.02,0.05,0.05,0.2\n",
       where + "2: empty image_name"},
      {kHeader + good + "\n" + good,
       where + "4: image 'a.png' already has a row at line 2"},
      {kHeader + good + "b.png,0,1,4,2,3,0,0,0,1,1,0.02,0.05,0.05,0.2\n",
       where + "3: time 0 s is not after the previous row of dive 1 (line 2, 0 "
               "s); the rows of a dive must come in strictly increasing time"},
      {kHeader + "a.png,5,1,4,2,3,0,0,0,1,1,0.02,0.05,0.05,0.2\n" +
           "b.png,6,2,4,2,3,0,0,0,1,1,0.02,0.05,0.05,0.2\n" +
           "c.png,4,1,4,2,3,0,0,0,1,1,0.02,0.05,0.05,0.2\n",
       where + "4: time 4 s is not after the previous row of dive 1 (line 2"},
      // Unix times in full, with their calendar time: not 1.72841e+09.
      {kHeader + "a.png,1728410000.25,1,4,2,3,0,0,0,1,1,0.02,0.05,0.05,0.2\n" +
           "b.png,1728410000.25,1,4,2,3,0,0,0,1,1,0.02,0.05,0.05,0.2\n",
       where + "3: time 1728410000.25 (2024-10-08T17:53:20.25Z) s is not "
               "after the previous row of dive 1 (line 2, 1728410000.25 "
               "(2024-10-08T17:53:20.25Z) s)"},
      {"image_name,time,x,y\n", where + "1: the positions are one of x,y,z"},
      {"time,x,y,z,lat,lon,depth\n1,0,0,0,43,5,10\n",
       where + "1: the positions are one of x,y,z"},
      {"time,lat,lon\n1,43,5\n", where + "1: the positions are one of"},
      {"time,x,y,z,depth\n1,0,0,0,10\n", where + "1: the positions are one of"},
      {"time,lat,lon,depth,alt\n1,43,5,1,1\n",
       where + "1: the positions are one of"},
      {"time,lat,lon,depth\n1,43,5,1\n2,95,5,1\n",
       where + "3: lat 95, lon 5 is not a position in degrees"},
      {"time,easting,northing,zone,alt\n1,500000,0,31n,0\n2,500000,0,31U,0\n",
       where + "3: zone '31U' is not a UTM zone with its hemisphere"},
      {"# no header\n" + good, where + "2: expected the header"},
      {kHeader, path_.string() + ": no navigation rows"},
      {"", path_.string() + ": no header row"},
  };
  for (const auto& test : cases) {
    const std::string message = Error(test.text);
    EXPECT_EQ(message.substr(0, test.message.size()), test.message)
        << "for:\n"
        << test.text;
  }
}

TEST_F(NavCsvTest, MissingFileIsNamed) {
  try {
    ReadNavigationCsv(path_);
    ADD_FAILURE() << "no error";
  } catch (const uw::Error& error) {
    EXPECT_EQ(std::string(error.what()),
              path_.string() + ": cannot open for reading");
  }
}

}  // namespace
}  // namespace uw
