#include "colmap_plugins/nav/nav_plausibility.h"

#include <gtest/gtest.h>

#include <cmath>

namespace uw {
namespace {

// A 40 m x 30 m lawnmower, as positions in metres from `origin`.
std::vector<NavRecord> Lawnmower(const Eigen::Vector2d& origin,
                                 double metres_per_unit_x = 1.0,
                                 double metres_per_unit_y = 1.0) {
  std::vector<NavRecord> nav;
  for (int k = 0; k < 40; ++k) {
    NavRecord row;
    row.time_s = k;
    row.position = Eigen::Vector3d(
        origin.x() + (k % 2 == 0 ? 0.0 : 40.0) / metres_per_unit_x,
        origin.y() + 30.0 * k / 39.0 / metres_per_unit_y, -12.0);
    nav.push_back(row);
  }
  return nav;
}

TEST(DegreesLikePositions, LongitudeAndLatitudeAreWarned) {
  const double metres_per_degree = 111320.0;
  const std::vector<NavRecord> nav =
      Lawnmower({5.4, 43.1}, metres_per_degree * std::cos(43.1 * M_PI / 180),
                metres_per_degree);
  const auto warning = DegreesLikePositionsWarning(nav, "nav.csv");
  ASSERT_TRUE(warning.has_value());
  EXPECT_EQ(warning->rfind("nav.csv: x and y span only 0.000492 x 0.000269 "
                           "around (5.400246, 43.100135): longitude and "
                           "latitude in degrees?",
                           0),
            0u)
      << *warning;
  // Latitude first, and the southern and western hemispheres.
  EXPECT_TRUE(DegreesLikePositionsWarning(
      Lawnmower({-33.9, -151.2}, metres_per_degree, metres_per_degree),
      "nav.csv"));
}

TEST(DegreesLikePositions, MetricLogsAreNot) {
  // Near the origin, far from it, in UTM, or a camera that stayed put at
  // the origin: none is warned.
  EXPECT_FALSE(DegreesLikePositionsWarning(Lawnmower({-20, -15}), "n"));
  EXPECT_FALSE(DegreesLikePositionsWarning(Lawnmower({43, 5}), "n"));
  EXPECT_FALSE(DegreesLikePositionsWarning(Lawnmower({4.5e5, 5.2e6}), "n"));
  EXPECT_FALSE(
      DegreesLikePositionsWarning(Lawnmower({0.01, 0}, 1e4, 1e4), "n"));
  // A single row has no extent to judge.
  EXPECT_FALSE(DegreesLikePositionsWarning(
      {Lawnmower({5.4, 43.1}, 1e5, 1e5).front()}, "n"));
}

}  // namespace
}  // namespace uw
