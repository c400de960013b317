#include "colmap_plugins/nav/geodesy.h"

#include <cmath>

#include <gtest/gtest.h>

#include "common/util/error_testing.h"

namespace uw {
namespace {

// WGS84 (a, e^2), for figures computed here independently of GeographicLib.
constexpr double kA = 6378137.0;
constexpr double kE2 = 6.69437999014e-3;
constexpr double kDegToRad = M_PI / 180.0;

double MeridionalRadius(double lat_deg) {
  const double s = std::sin(lat_deg * kDegToRad);
  return kA * (1.0 - kE2) / std::pow(1.0 - kE2 * s * s, 1.5);
}
double PrimeVerticalRadius(double lat_deg) {
  const double s = std::sin(lat_deg * kDegToRad);
  return kA / std::sqrt(1.0 - kE2 * s * s);
}

TEST(Geodesy, SmallStepsAreTheEllipsoidsRadiiTimesTheAngle) {
  const LocalEnu local({45.0, 5.0, 0.0});
  // 1e-4 deg (11 m): the arc differs from radius x angle by < 1 um.
  const double step = 1e-4;
  const Eigen::Vector3d north = local.FromGeodetic(45.0 + step, 5.0, 0.0);
  const double expected_north = MeridionalRadius(45.0) * step * kDegToRad;
  EXPECT_NEAR(north.y(), expected_north, 1e-5);
  EXPECT_NEAR(north.x(), 0.0, 1e-9);
  // The surface falls away from the tangent plane by d^2 / 2R.
  EXPECT_NEAR(north.z(),
              -expected_north * expected_north / (2.0 * MeridionalRadius(45.0)),
              1e-7);
  const Eigen::Vector3d east = local.FromGeodetic(45.0, 5.0 + step, 0.0);
  EXPECT_NEAR(
      east.x(),
      PrimeVerticalRadius(45.0) * std::cos(45.0 * kDegToRad) * step * kDegToRad,
      1e-5);
  // Depth is height below the origin's datum.
  EXPECT_NEAR(local.FromGeodetic(45.0, 5.0, -30.0).z(), -30.0, 1e-9);
}

TEST(Geodesy, RoundTripsToTheMicrometreKilometresAway) {
  const LocalEnu local({-33.9, 151.2, 0.0});
  for (const Eigen::Vector3d& enu :
       {Eigen::Vector3d(0.0, 0.0, 0.0), Eigen::Vector3d(5000.0, -3000.0, -40.0),
        Eigen::Vector3d(-12000.0, 8000.0, -2500.0)}) {
    const Eigen::Vector3d geodetic = local.ToGeodetic(enu);
    EXPECT_LT((local.FromGeodetic(geodetic(0), geodetic(1), geodetic(2)) - enu)
                  .norm(),
              1e-6);
  }
}

// The central meridian of zone 31 is 3 deg E: on the equator it lies at
// easting 500 000 m, northing 0 (north) or 10 000 000 m (south).
TEST(Geodesy, UtmAtAZonesCentralMeridian) {
  const LocalEnu local({0.001, 3.0, 0.0});
  const Eigen::Vector3d expected = local.FromGeodetic(0.0, 3.0, -5.0);
  EXPECT_LT((local.FromUtm(31, true, 500000.0, 0.0, -5.0) - expected).norm(),
            1e-6);
  EXPECT_LT(
      (local.FromUtm(31, false, 500000.0, 10000000.0, -5.0) - expected).norm(),
      1e-6);
  // 100 m east of the meridian: the UTM scale there is 0.9996.
  const Eigen::Vector3d east = local.FromUtm(31, true, 500100.0, 0.0, 0.0);
  EXPECT_NEAR(east.x() - expected.x(), 100.0 / 0.9996, 1e-3);
}

TEST(Geodesy, HeadingTurnsClockwiseFromTrueNorth) {
  const LocalEnu local({45.0, 5.0, 0.0});
  EXPECT_NEAR(local.YawFromHeading(0.0, 45.0, 5.0, 0.0), 90.0, 1e-9);
  EXPECT_NEAR(local.YawFromHeading(90.0, 45.0, 5.0, 0.0), 0.0, 1e-9);
  EXPECT_NEAR(local.YawFromHeading(180.0, 45.0, 5.0, 0.0), -90.0, 1e-9);
  EXPECT_NEAR(local.YawFromHeading(-45.0, 45.0, 5.0, 0.0), 135.0, 1e-9);
}

// 10 km east at 45 deg N, north leans west of the origin's north by the
// convergence of the meridians, dlon sin(lat) (0.0897 deg).
TEST(Geodesy, HeadingAwayFromTheOriginIncludesTheMeridiansConvergence) {
  const LocalEnu local({45.0, 5.0, 0.0});
  const double dlon_deg =
      10000.0 / (PrimeVerticalRadius(45.0) * std::cos(45.0 * kDegToRad)) /
      kDegToRad;
  const double convergence_deg = dlon_deg * std::sin(45.0 * kDegToRad);
  EXPECT_NEAR(convergence_deg, 0.0897, 1e-4);
  const double yaw = local.YawFromHeading(0.0, 45.0, 5.0 + dlon_deg, 0.0);
  EXPECT_NEAR(yaw, 90.0 + convergence_deg, 2e-4);
  const Eigen::Vector3d fix = local.FromGeodetic(45.0, 5.0 + dlon_deg, 0.0);
  for (const double heading : {0.0, 37.5, 181.0, -100.0}) {
    const double there =
        local.YawFromHeading(heading, 45.0, 5.0 + dlon_deg, 0.0);
    const double back = local.HeadingFromYaw(there, fix);
    EXPECT_NEAR(std::remainder(back - heading, 360.0), 0.0, 1e-9);
  }
}

TEST(Geodesy, ZonesNeedTheirHemisphere) {
  int zone = 0;
  bool north = false;
  ParseUtmZone("31n", "nav.csv:2", &zone, &north);
  EXPECT_EQ(zone, 31);
  EXPECT_TRUE(north);
  ParseUtmZone("5S", "nav.csv:2", &zone, &north);
  EXPECT_EQ(zone, 5);
  EXPECT_FALSE(north);
  ParseUtmZone("60north", "nav.csv:2", &zone, &north);
  EXPECT_EQ(zone, 60);
  for (const char* bad : {"31U", "31", "0n", "61n", "n", "", "x"}) {
    ExpectErrorContaining(
        [&] { ParseUtmZone(bad, "nav.csv:7", &zone, &north); },
        "nav.csv:7: zone '");
  }
}

TEST(Geodesy, OriginsAreReadAndChecked) {
  const GeoOrigin origin = GeoOriginFromText("43.25,5.375", "--origin");
  EXPECT_EQ(origin.lat_deg, 43.25);
  EXPECT_EQ(origin.lon_deg, 5.375);
  EXPECT_EQ(origin.height_m, 0.0);
  EXPECT_EQ(GeoOriginFromText("-43.25,185,-2.5", "--origin").height_m, -2.5);
  EXPECT_EQ(GeoOriginFromText("43.25, 5.375", "--origin").lon_deg, 5.375);
  EXPECT_EQ(GeoOriginText(origin), "43.250000000,5.375000000,0.0000");
  for (const char* bad : {"43.25", "43.25,5,1,2", "a,5", "43.25,5x", ""}) {
    ExpectErrorContaining([&] { GeoOriginFromText(bad, "--origin"); },
                          "--origin: '");
  }
  ExpectErrorContaining([] { GeoOriginFromText("95,5", "--origin"); },
                        "latitude first");
  ExpectErrorContaining([] { GeoOriginFromText("45,400", "--origin"); },
                        "longitude 400");
  const GeoOrigin automatic = AutomaticOrigin(43.123456, -5.4567);
  EXPECT_NEAR(automatic.lat_deg, 43.123, 1e-12);
  EXPECT_NEAR(automatic.lon_deg, -5.457, 1e-12);
}

}  // namespace
}  // namespace uw
