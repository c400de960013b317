#include "colmap_plugins/nav/ugps_csv.h"

#include <fstream>

#include <fmt/format.h>

#include <gtest/gtest.h>

#include "colmap_plugins/nav/nav_log.h"
#include "common/util/error_testing.h"
#include "tests/support/process.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

class UgpsLogTest : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = testing::FreshTestDir("uw_ugps_csv_test"); }
  fs::path Write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name, std::ios::binary) << text;
    return dir_ / name;
  }
  fs::path dir_;
};

// As wl_ugps_logger.py writes GET /api/v1/position/acoustic/filtered: the
// API's keys, its lists flattened, Python's True/False, a Unix timestamp.
const std::string kHeader =
    "position_valid,std,x,y,z,distance_r0,distance_r1,nsd_r0,nsd_r1,"
    "rssi_r0,rssi_r1,valid_r0,valid_r1,timestamp\n";

std::string Row(bool valid, double x, double y, double z, double time) {
  return fmt::format("{},0.25,{},{},{},20.1,20.3,-50,-51,-20,-21,1,1,{}\n",
                     valid ? "True" : "False", x, y, z, time);
}

// x is forward along the topside's heading, y to starboard, z the depth:
// heading 90 puts x east and y south, heading 0 x north and y east.
TEST_F(UgpsLogTest, AxesTurnWithTheTopsidesHeading) {
  const fs::path log =
      Write("filtered.csv", kHeader + Row(true, 10, 0, 5, 1728410000.5) +
                                Row(false, 99, 99, 99, 1728410001.0) +
                                Row(true, 0, 3, 6, 1728410001.5));
  EXPECT_TRUE(LooksLikeUgpsLog(log));
  const GeoOrigin origin{43.0, 5.0, 0.0};
  UgpsOptions options;
  options.topside = UgpsTopside{0.0, 43.0, 5.0, 90.0};
  NavLogFrame frame;
  std::vector<NavRecord> nav = ReadUgpsLog(log, options, origin, &frame);
  ASSERT_EQ(nav.size(), 2u);
  EXPECT_EQ(frame.position_columns, "Water Linked x,y,z");
  ASSERT_EQ(frame.notes.size(), 1u);
  EXPECT_NE(frame.notes[0].find("1 rows with position_valid False left out"),
            std::string::npos);
  EXPECT_TRUE(nav[0].position.isApprox(Eigen::Vector3d(10, 0, -5), 1e-9))
      << nav[0].position.transpose();
  EXPECT_TRUE(nav[1].position.isApprox(Eigen::Vector3d(0, -3, -6), 1e-9))
      << nav[1].position.transpose();
  EXPECT_EQ(nav[0].time_s, 1728410000.5);
  EXPECT_EQ(nav[0].position_sigma, Eigen::Vector3d::Constant(0.25));
  EXPECT_FALSE(nav[0].has_roll_pitch);
  EXPECT_FALSE(nav[0].has_yaw);

  options.topside->heading_deg = 0.0;
  nav = ReadUgpsLog(log, options, origin, nullptr);
  EXPECT_TRUE(nav[0].position.isApprox(Eigen::Vector3d(0, 10, -5), 1e-9))
      << nav[0].position.transpose();
  EXPECT_TRUE(nav[1].position.isApprox(Eigen::Vector3d(3, 0, -6), 1e-9))
      << nav[1].position.transpose();

  // Through ReadNavigationLog: found by its header, the topside required.
  NavLogOptions log_options;
  log_options.origin = origin;
  ExpectErrorContaining([&] { ReadNavigationLog(log, log_options); },
                        "give either --ugps_topside lat,lon,heading");
  log_options.ugps = options;
  EXPECT_EQ(ReadNavigationLog(log, log_options).size(), 2u);
  // ... and not taken for any other log.
  const fs::path csv = Write("nav.csv", "time,x,y,z\n0,1,2,3\n");
  ExpectErrorContaining([&] { ReadNavigationLog(csv, log_options); },
                        "--ugps_topside and --ugps_master are for a Water "
                        "Linked log, and this is csv");
}

// A topside on a boat: its own log (GET /api/v1/position/master) is
// interpolated at each acoustic row, the heading along its shorter arc.
TEST_F(UgpsLogTest, AMovingTopsideIsInterpolated) {
  const fs::path log =
      Write("filtered.csv",
            kHeader + Row(true, 10, 0, 5, 101.0) + Row(true, 10, 0, 5, 103.5));
  UgpsOptions options;
  options.master_path =
      Write("master.csv",
            "cog,fix_quality,hdop,lat,lon,numsats,orientation,sog,timestamp\n"
            "0,1,0.9,43.0,5.0,9,350,0,100\n"
            "0,1,0.9,43.0,5.0,9,-1,0,101.5\n"  // no compass reading
            "0,1,0.9,43.0,5.0,9,10,0,102\n")
          .string();
  const GeoOrigin origin{43.0, 5.0, 0.0};
  ExpectErrorContaining([&] { ReadUgpsLog(log, options, origin, nullptr); },
                        "filtered.csv:3: timestamp 103.5 lies outside the "
                        "topside log");
  Write("filtered.csv", kHeader + Row(true, 10, 0, 5, 101.0));
  const std::vector<NavRecord> nav = ReadUgpsLog(log, options, origin, nullptr);
  ASSERT_EQ(nav.size(), 1u);
  // Halfway from 350 to 10 deg: north.
  EXPECT_TRUE(nav[0].position.isApprox(Eigen::Vector3d(0, 10, -5), 1e-9))
      << nav[0].position.transpose();
}

TEST_F(UgpsLogTest, BadInputIsNamed) {
  UgpsOptions options;
  options.topside = UgpsTopside{0.0, 43.0, 5.0, 0.0};
  ExpectErrorContaining(
      [&] {
        ReadUgpsLog(Write("a.csv", kHeader + Row(true, 1, 0, 1, 5) +
                                       Row(true, 1, 0, 1, 5)),
                    options, std::nullopt, nullptr);
      },
      "a.csv:3: timestamp 5 is not after the previous row's (line 2, 5)");
  ExpectErrorContaining(
      [&] {
        ReadUgpsLog(Write("b.csv",
                          "position_valid,x,y,z,timestamp\n"
                          "maybe,1,0,1,5\n"),
                    options, std::nullopt, nullptr);
      },
      "b.csv:2: position_valid must be True or False, got 'maybe'");
  ExpectErrorContaining(
      [&] {
        ReadUgpsLog(Write("c.csv", kHeader + Row(false, 1, 0, 1, 5)), options,
                    std::nullopt, nullptr);
      },
      "c.csv: no valid position (1 rows with position_valid False)");
  ExpectErrorContaining(
      [&] {
        ReadUgpsLog(Write("d.csv", "x,y,timestamp\n1,2,3\n"), options,
                    std::nullopt, nullptr);
      },
      "d.csv:1: a Water Linked acoustic log needs the column 'z'");
  ExpectErrorContaining([] { UgpsTopsideFromText("43,5", "--ugps_topside"); },
                        "--ugps_topside '43,5': expected lat,lon,heading");
  options.master_path = "master.csv";
  ExpectErrorContaining([&] { options.Check(); }, "give either");
}

}  // namespace
}  // namespace uw
