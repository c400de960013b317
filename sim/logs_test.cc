#include "sim/logs.h"

#include <gtest/gtest.h>

#include "common/util/error_testing.h"

namespace uw::sim {
namespace {

TEST(LogOptions, RefusesWhatCannotBeWritten) {
  LogOptions options;
  options.Check();
  EXPECT_FALSE(options.ClockStart());
  options.clock_start = "2024-10-08T14:00:00+02:00";
  EXPECT_EQ(options.ClockStart(), 1728388800.0);
  options.camera_zone = "-05:30";
  EXPECT_EQ(options.CameraZoneOffset(), -19800);

  const auto message = [](const LogOptions& bad) {
    return ErrorOf([&] { bad.Check(); });
  };
  LogOptions bad;
  bad.exif_times = true;
  EXPECT_NE(message(bad).find("logs.exif_times needs logs.clock_start"),
            std::string::npos);
  bad = LogOptions();
  bad.clock_start = "2024-10-08 12:00:00";
  EXPECT_NE(message(bad).find("logs.clock_start: '2024-10-08 12:00:00' has "
                              "no time zone"),
            std::string::npos);
  bad = LogOptions();
  bad.camera_zone = "CET";
  EXPECT_NE(message(bad).find("logs.camera_zone"), std::string::npos);
  bad = LogOptions();
  bad.nav_formats = {"wgs84"};
  EXPECT_NE(message(bad).find("needs logs.geodetic_origin"), std::string::npos);
  bad.geodetic_origin = "43.25,5.375";
  EXPECT_EQ(message(bad), "");
  bad.nav_formats = {"nmea"};
  EXPECT_NE(message(bad).find("\"nmea\" needs logs.clock_start"),
            std::string::npos);
  bad.nav_formats = {"gpx"};
  EXPECT_NE(message(bad).find("unknown format 'gpx'"), std::string::npos);
  bad.nav_formats = {"wgs84"};
  bad.geodetic_origin = "43.25,5.375,-10";
  EXPECT_NE(message(bad).find("site_depth_m"), std::string::npos);
}

TEST(LogOptions, TheGeographicFrameIsNavCsvsFrame) {
  LogOptions options;
  options.geodetic_origin = "-12.25,130.75";
  const GeoOrigin origin = options.Origin(80.0);
  EXPECT_EQ(origin.lat_deg, -12.25);
  EXPECT_EQ(origin.lon_deg, 130.75);
  EXPECT_EQ(origin.height_m, -80.0);
}

NavigationRecord Record(double time_s, const Eigen::Vector3d& position,
                        double yaw_deg) {
  NavigationRecord record;
  record.image_name = "a.png";
  record.time_s = time_s;
  record.position = position;
  record.rpy = Eigen::Vector3d(0.0, 0.0, yaw_deg * M_PI / 180.0);
  return record;
}

// The sentences a logger writes: checksums, hemispheres, a heading from 0
// to 360, minutes that round up carried into the degrees, and a ZDA again
// when the UTC day changes.
TEST(NmeaNavigationLog, WritesSentencesALoggerWrites) {
  const LocalEnu local(GeoOrigin{-12.0, -130.0, -100.0});
  const double midnight = 1728432000.0;  // 2024-10-09T00:00:00Z
  const std::string log = NmeaNavigationLog(
      {Record(midnight - 0.25, {0, 0, 95}, 90.0),
       Record(midnight + 1.5,
              local.FromGeodetic(-12.999999999999, -130.0, -5.0), 0.0)},
      local);
  EXPECT_NE(log.find("$GPZDA,235959.750000,08,10,2024,00,00*"),
            std::string::npos)
      << log;
  EXPECT_NE(log.find("$GPZDA,000001.500000,09,10,2024,00,00*"),
            std::string::npos)
      << log;
  // Yaw 90 (north) is heading 0; yaw 0 (east) heading 90.
  EXPECT_NE(log.find("$HEHDT,0.00000000,T*"), std::string::npos) << log;
  EXPECT_NE(log.find("$HEHDT,90.00000000,T*"), std::string::npos) << log;
  EXPECT_NE(log.find(",1200.00000000,S,13000.00000000,W,1,12,0.8,-5.000000,"),
            std::string::npos)
      << log;
  // 12 deg 59.99999999994 min is written 13 deg, not 12 deg 60 min.
  EXPECT_NE(log.find(",1300.00000000,S,13000.00000000,W,"), std::string::npos)
      << log;
  for (size_t start = log.find('$'); start != std::string::npos;
       start = log.find('$', start + 1)) {
    const size_t star = log.find('*', start);
    unsigned checksum = 0;
    for (size_t i = start + 1; i < star; ++i) {
      checksum ^= static_cast<unsigned char>(log[i]);
    }
    EXPECT_EQ(std::stoul(log.substr(star + 1, 2), nullptr, 16), checksum);
  }
}

}  // namespace
}  // namespace uw::sim
